#include "i2c_bus_server.h"

#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <robot_core/realtime.h>

namespace robot_sim {

namespace {
std::mutex g_registry_mutex;
std::map<std::string, std::weak_ptr<I2cBusServer>> g_registry;

void makeParents(const std::string& path) {
  for (std::size_t i = 1; i < path.size(); ++i)
    if (path[i] == '/') ::mkdir(path.substr(0, i).c_str(), 0777);
}
}  // namespace

std::string simBusPath(const std::string& url, const std::string& param) {
  if (url.rfind("sim:///", 0) != 0)
    throw std::runtime_error("parameter " + param + " = '" + url + "': must be sim:///PATH (the emulated bus socket)");
  return url.substr(6);
}

std::shared_ptr<I2cBusServer> I2cBusServer::attach(const std::string& path, uint8_t address, I2cSlave* slave) {
  std::shared_ptr<I2cBusServer> bus;
  {
    std::lock_guard<std::mutex> lk(g_registry_mutex);
    bus = g_registry[path].lock();
    if (!bus) {
      bus = std::make_shared<I2cBusServer>(path);
      g_registry[path] = bus;
    }
  }
  std::lock_guard<std::mutex> lk(bus->mutex_);
  if (bus->slaves_.count(address)) {
    char b[96];
    std::snprintf(b, sizeof(b), "address 0x%02x is already taken on the emulated bus ", address);
    throw std::runtime_error(b + path);
  }
  bus->slaves_[address] = slave;
  return bus;
}

void I2cBusServer::detach(uint8_t address) {
  std::lock_guard<std::mutex> lk(mutex_);
  slaves_.erase(address);
}

I2cBusServer::I2cBusServer(const std::string& path) : path_(path) {
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (path.size() >= sizeof(addr.sun_path)) throw std::runtime_error("I2C bus socket path too long: " + path);
  std::strncpy(addr.sun_path, path.c_str(), sizeof(addr.sun_path) - 1);
  makeParents(path);
  ::unlink(path.c_str());  // a socket left by a previous run
  listen_fd_ = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
  if (listen_fd_ < 0 || ::bind(listen_fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0 ||
      ::listen(listen_fd_, 8) != 0) {
    const std::string why = std::strerror(errno);
    if (listen_fd_ >= 0) ::close(listen_fd_);
    throw std::runtime_error("cannot serve the emulated I2C bus at " + path + ": " + why);
  }
  thread_ = std::thread([this] { serve(); });
}

I2cBusServer::~I2cBusServer() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
  ::close(listen_fd_);
  ::unlink(path_.c_str());
}

void I2cBusServer::serve() {
  robot_core::enterRealtime("the I2C bus emulator");  // the chips answer within the transaction
  std::vector<int> clients;
  uint8_t buf[4096];
  while (running_) {
    std::vector<pollfd> fds{{listen_fd_, POLLIN, 0}};
    for (int c : clients) fds.push_back({c, POLLIN, 0});
    if (::poll(fds.data(), fds.size(), 50) <= 0) continue;
    if (fds[0].revents & POLLIN) {
      const int c = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
      if (c >= 0) clients.push_back(c);
    }
    for (std::size_t i = 1; i < fds.size(); ++i) {
      if (!fds[i].revents) continue;
      const ssize_t n = ::recv(fds[i].fd, buf, sizeof(buf), 0);
      if (n <= 0) {  // master went away
        ::close(fds[i].fd);
        clients.erase(std::find(clients.begin(), clients.end(), fds[i].fd));
        continue;
      }
      const auto answer = execute(buf, static_cast<std::size_t>(n));
      ::send(fds[i].fd, answer.data(), answer.size(), MSG_NOSIGNAL);
    }
  }
  for (int c : clients) ::close(c);
}

// One combined transaction. A NACK ends it (the master sends a stop), as on the wire.
std::vector<uint8_t> I2cBusServer::execute(const uint8_t* req, std::size_t n) {
  std::vector<uint8_t> out = {'I', 'A', n >= 4 ? req[2] : uint8_t(0), n >= 4 ? req[3] : uint8_t(0), 0};
  auto busError = [&] {
    ++malformed_;
    out.resize(5);
    out[4] = 2;
    return out;
  };
  if (n < 5 || req[0] != 'I' || req[1] != 'Q') return busError();
  const std::size_t count = req[4];
  std::size_t at = 5;
  std::lock_guard<std::mutex> lk(mutex_);
  for (std::size_t m = 0; m < count; ++m) {
    if (at + 4 > n) return busError();
    const uint8_t address = req[at];
    const bool read = req[at + 1] & 0x01;
    const std::size_t len = req[at + 2] | (req[at + 3] << 8);
    at += 4;
    if (!read && at + len > n) return busError();
    auto it = slaves_.find(address);
    if (it == slaves_.end() || !it->second->acknowledge()) {
      out.resize(5);
      out[4] = 1;  // NACK
      return out;
    }
    if (read) {
      const std::size_t old = out.size();
      out.resize(old + len);
      it->second->i2cRead(out.data() + old, len);
    } else {
      it->second->i2cWrite(req + at, len);
      at += len;
    }
  }
  return out;
}

}  // namespace robot_sim
