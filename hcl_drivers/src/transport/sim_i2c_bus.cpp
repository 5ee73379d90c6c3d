#include "hcl_drivers/transport/sim_i2c_bus.h"

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

#include "hcl_drivers/transport/sim_i2c_protocol.h"

namespace hcl_drivers {
namespace transport {

namespace sim_i2c {

std::vector<uint8_t> encodeRequest(uint16_t seq, const std::vector<I2cMessage>& msgs) {
  std::vector<uint8_t> p = {kMagic, kRequest, static_cast<uint8_t>(seq), static_cast<uint8_t>(seq >> 8),
                            static_cast<uint8_t>(msgs.size())};
  for (const auto& m : msgs) {
    const auto len = static_cast<uint16_t>(m.data.size());
    p.insert(p.end(), {m.address, static_cast<uint8_t>(m.read ? kFlagRead : 0), static_cast<uint8_t>(len),
                       static_cast<uint8_t>(len >> 8)});
    if (!m.read) p.insert(p.end(), m.data.begin(), m.data.end());
  }
  return p;
}

std::optional<Answer> decodeAnswer(const uint8_t* d, std::size_t n) {
  if (n < 5 || d[0] != kMagic || d[1] != kAnswer || d[4] > kStatusBusError) return std::nullopt;
  Answer a;
  a.seq = static_cast<uint16_t>(d[2] | (d[3] << 8));
  a.status = d[4];
  a.read_bytes.assign(d + 5, d + n);
  return a;
}

}  // namespace sim_i2c

SimI2cBus::SimI2cBus(const std::string& url, const std::string& socket_path) : I2cBus(url), path_(socket_path) {}

SimI2cBus::~SimI2cBus() { disconnect(); }

bool SimI2cBus::connect(std::string& detail) {
  if (fd_ >= 0) return true;
  fd_ = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (path_.size() >= sizeof(addr.sun_path)) {
    detail = "socket path too long: " + path_;
    disconnect();
    return false;
  }
  std::strncpy(addr.sun_path, path_.c_str(), sizeof(addr.sun_path) - 1);
  if (fd_ < 0 || ::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
    detail = "no emulator at " + path_ + ": " + std::strerror(errno);
    disconnect();
    return false;
  }
  return true;
}

void SimI2cBus::disconnect() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

I2cStatus SimI2cBus::transferOnce(std::vector<I2cMessage>& msgs, std::string& detail) {
  if (!connect(detail)) return I2cStatus::kBusError;
  const uint16_t seq = ++seq_;
  const auto request = sim_i2c::encodeRequest(seq, msgs);
  if (::send(fd_, request.data(), request.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(request.size())) {
    detail = std::string("send: ") + std::strerror(errno);
    disconnect();  // the emulator went away; reconnect next time
    return I2cStatus::kBusError;
  }
  std::size_t expected = 0;
  for (const auto& m : msgs)
    if (m.read) expected += m.data.size();
  // The reply window is wall time: the emulated bus answers in wall time, as /dev/i2c-N does.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout());
  uint8_t buf[sim_i2c::kMaxPacket];
  while (true) {
    const double left = std::chrono::duration<double>(deadline - std::chrono::steady_clock::now()).count();
    pollfd p{fd_, POLLIN, 0};
    if (left <= 0.0 || ::poll(&p, 1, static_cast<int>(left * 1000.0) + 1) <= 0) {
      detail = "no answer within " + std::to_string(static_cast<int>(timeout() * 1000)) + " ms";
      return I2cStatus::kTimeout;
    }
    const ssize_t n = ::recv(fd_, buf, sizeof(buf), 0);
    if (n <= 0) {
      detail = n == 0 ? "emulator closed the bus" : std::string("recv: ") + std::strerror(errno);
      disconnect();
      return I2cStatus::kBusError;
    }
    const auto answer = sim_i2c::decodeAnswer(buf, static_cast<std::size_t>(n));
    if (!answer || answer->seq != seq) continue;  // malformed, or late answer to an abandoned request
    if (answer->status == sim_i2c::kStatusNack) return I2cStatus::kNack;
    if (answer->status != sim_i2c::kStatusOk) {
      detail = "emulated bus error";
      return I2cStatus::kBusError;
    }
    if (answer->read_bytes.size() != expected) {
      detail = "answer has " + std::to_string(answer->read_bytes.size()) + " bytes, expected " + std::to_string(expected);
      return I2cStatus::kBusError;
    }
    std::size_t at = 0;
    for (auto& m : msgs) {
      if (!m.read) continue;
      std::copy(answer->read_bytes.begin() + at, answer->read_bytes.begin() + at + m.data.size(), m.data.begin());
      at += m.data.size();
    }
    return I2cStatus::kOk;
  }
}

}  // namespace transport
}  // namespace hcl_drivers
