#include "hcl_drivers/transport/udp_can_bus.h"

#include <arpa/inet.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <system_error>

#include <robot_core/realtime.h>

#include "receive_timestamp.h"

namespace hcl_drivers {
namespace transport {

namespace {
constexpr double kKeepalivePeriod = 0.2;  // [s] client HELLO period
constexpr double kPeerExpiry = 2.0;       // [s] hub forgets a silent participant
constexpr double kHubProbePeriod = 0.3;   // [s] client tries to take over the hub port
constexpr std::size_t kQueueLimit = 1024;

double nowS() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
uint64_t key(const sockaddr_in& a) { return (static_cast<uint64_t>(a.sin_addr.s_addr) << 16) | a.sin_port; }

int makeSocket() {
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) throw std::system_error(errno, std::generic_category(), "socket(AF_INET, SOCK_DGRAM)");
  int buf = 1 << 20;
  ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &buf, sizeof(buf));
  enableReceiveTimestamps(fd);  // CanFrame::received
  return fd;
}
}  // namespace

class UdpCanBus::Channel : public CanChannel {
 public:
  Channel(std::shared_ptr<UdpCanBus> bus, std::vector<CanFilter> filters)
      : bus_(std::move(bus)), filters_(std::move(filters)) {}
  ~Channel() override { bus_->close(this); }

  bool send(const CanFrame& f) override { return bus_->sendFrom(this, f, last_error_); }

  bool receive(CanFrame& f, double timeout_s) override {
    std::unique_lock<std::mutex> lk(mutex_);
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s > 0 ? timeout_s : 0);
    if (!cv_.wait_until(lk, until, [this] { return !queue_.empty(); })) {
      last_error_ = "timeout";
      return false;
    }
    f = queue_.front();
    queue_.pop_front();
    return true;
  }

  void drain() override {
    std::lock_guard<std::mutex> lk(mutex_);
    queue_.clear();
  }

  bool wants(const CanFrame& f) const {
    if (filters_.empty()) return !f.error;
    for (const auto& flt : filters_)
      if (flt.matches(f)) return true;
    return false;
  }

  // False when the queue overflowed (frame dropped).
  bool push(const CanFrame& f) {
    {
      std::lock_guard<std::mutex> lk(mutex_);
      if (queue_.size() >= kQueueLimit) return false;
      queue_.push_back(f);
    }
    cv_.notify_one();
    return true;
  }

 private:
  std::shared_ptr<UdpCanBus> bus_;
  std::vector<CanFilter> filters_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<CanFrame> queue_;
};

UdpCanBus::UdpCanBus(const std::string& url, const std::string& host, uint16_t port) : CanBus(url) {
  hub_addr_.sin_family = AF_INET;
  hub_addr_.sin_port = htons(port);
  if (::inet_pton(AF_INET, host.c_str(), &hub_addr_.sin_addr) != 1)
    throw std::system_error(EINVAL, std::generic_category(), "not an IPv4 address: " + host);
  if (!tryBecomeHub()) {
    const int fd = makeSocket();
    sockaddr_in any = hub_addr_;
    any.sin_port = 0;
    if (::bind(fd, reinterpret_cast<sockaddr*>(&any), sizeof(any)) != 0) {
      const int err = errno;
      ::close(fd);
      throw std::system_error(err, std::generic_category(), "bind " + host + ":0");
    }
    fd_ = fd;
    const auto hello = udp_can::encodeHello();
    ::sendto(fd, hello.data(), hello.size(), 0, reinterpret_cast<const sockaddr*>(&hub_addr_), sizeof(hub_addr_));
  }
  thread_ = std::thread([this] { run(); });
}

UdpCanBus::~UdpCanBus() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
  if (fd_ >= 0) ::close(fd_);
}

bool UdpCanBus::tryBecomeHub() {
  const int fd = makeSocket();
  // No SO_REUSEADDR: with it two UDP sockets could bind the same port and both be "hub".
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&hub_addr_), sizeof(hub_addr_)) != 0) {
    ::close(fd);
    return false;
  }
  const int old = fd_.exchange(fd);
  hub_ = true;
  // The old client socket is closed by this (receiving) thread only after the swap, so a
  // concurrent sendto on it at worst fails once.
  if (old >= 0) ::close(old);
  return true;
}

std::shared_ptr<CanChannel> UdpCanBus::open(const std::vector<CanFilter>& filters) {
  auto ch = std::make_shared<Channel>(shared_from_this(), filters);
  std::lock_guard<std::mutex> lk(mutex_);
  channels_.push_back(ch.get());
  return ch;
}

void UdpCanBus::close(Channel* ch) {
  std::lock_guard<std::mutex> lk(mutex_);
  for (auto it = channels_.begin(); it != channels_.end(); ++it)
    if (*it == ch) {
      channels_.erase(it);
      break;
    }
}

void UdpCanBus::deliverLocal(const CanFrame& f, const Channel* except) {
  unsigned long dropped = 0;
  {
    std::lock_guard<std::mutex> lk(mutex_);
    for (Channel* ch : channels_)
      if (ch != except && ch->wants(f) && !ch->push(f)) ++dropped;
  }
  if (dropped) {
    std::lock_guard<std::mutex> lk(status_mutex_);
    status_.overruns += dropped;
  }
}

bool UdpCanBus::sendFrom(Channel* sender, const CanFrame& f, std::string& error) {
  if (f.dlc > 8) {
    error = "dlc > 8";
    return false;
  }
  {
    std::lock_guard<std::mutex> lk(status_mutex_);
    if (status_.state == BusState::kBusOff && !f.error) {
      ++status_.tx_failures;
      error = "bus-off: " + status_.last_error;
      return false;
    }
  }
  const auto d = udp_can::encode(f);
  bool ok = true;
  const int fd = fd_;
  if (hub_) {
    std::vector<sockaddr_in> peers;
    {
      std::lock_guard<std::mutex> lk(mutex_);
      for (const auto& kv : peers_) peers.push_back(kv.second.first);
    }
    for (const auto& p : peers)
      ::sendto(fd, d.data(), d.size(), 0, reinterpret_cast<const sockaddr*>(&p), sizeof(p));
  } else if (::sendto(fd, d.data(), d.size(), 0, reinterpret_cast<const sockaddr*>(&hub_addr_), sizeof(hub_addr_)) !=
             static_cast<ssize_t>(d.size())) {
    // ECONNREFUSED here is a previous datagram's "port unreachable": the hub is gone and
    // will be replaced; the frame is lost like on a bus without a receiver.
    error = std::string("sendto hub: ") + std::strerror(errno);
    ok = false;
  }
  deliverLocal(f, sender);
  std::lock_guard<std::mutex> lk(status_mutex_);
  if (ok)
    ++status_.tx_frames;
  else
    ++status_.tx_failures;
  return ok;
}

void UdpCanBus::handleDatagram(const uint8_t* buf, std::size_t n, const sockaddr_in& from, double received) {
  uint8_t kind = 0;
  auto f = udp_can::decode(buf, n, &kind);
  if (!f) {
    std::lock_guard<std::mutex> lk(status_mutex_);
    ++status_.malformed;
    return;
  }
  if (hub_) {
    std::vector<sockaddr_in> peers;
    {
      std::lock_guard<std::mutex> lk(mutex_);
      peers_[key(from)] = {from, nowS()};
      if (kind == udp_can::kKindFrame)
        for (const auto& kv : peers_)
          if (kv.first != key(from)) peers.push_back(kv.second.first);
    }
    for (const auto& p : peers)
      ::sendto(fd_, buf, n, 0, reinterpret_cast<const sockaddr*>(&p), sizeof(p));
  }
  if (kind != udp_can::kKindFrame) return;
  if (f->error) {
    std::lock_guard<std::mutex> lk(status_mutex_);
    status_.apply(decodeErrorFrame(*f), nowS());
    return;
  }
  {
    std::lock_guard<std::mutex> lk(status_mutex_);
    status_.frameReceived(nowS());
    if (status_.state == BusState::kBusOff) return;  // a bus-off controller receives nothing
  }
  f->received = received;
  deliverLocal(*f, nullptr);
}

void UdpCanBus::run() {
  robot_core::enterRealtime("the CAN bus reader (udp)");  // frames reach their channels at once
  double next_hello = 0.0, next_probe = nowS() + kHubProbePeriod, next_expiry = 0.0;
  uint8_t buf[64];
  while (running_) {
    const double now = nowS();
    if (!hub_) {
      if (now >= next_hello) {
        const auto hello = udp_can::encodeHello();
        ::sendto(fd_, hello.data(), hello.size(), 0, reinterpret_cast<const sockaddr*>(&hub_addr_), sizeof(hub_addr_));
        next_hello = now + kKeepalivePeriod;
      }
      if (now >= next_probe) {
        tryBecomeHub();
        next_probe = now + kHubProbePeriod;
      }
    } else if (now >= next_expiry) {
      std::lock_guard<std::mutex> lk(mutex_);
      for (auto it = peers_.begin(); it != peers_.end();)
        it = now - it->second.second > kPeerExpiry ? peers_.erase(it) : std::next(it);
      next_expiry = now + 0.5;
    }
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, 50) <= 0) continue;
    // Drain everything queued before going back to the timers.
    while (true) {
      sockaddr_in from{};
      double received = 0.0;
      const ssize_t n = receiveStamped(fd_, buf, sizeof(buf), MSG_DONTWAIT, &received,
                                       reinterpret_cast<sockaddr*>(&from), sizeof(from));
      if (n < 0) break;  // EAGAIN, or ECONNREFUSED from a vanished hub
      handleDatagram(buf, static_cast<std::size_t>(n), from, received);
    }
  }
}

}  // namespace transport
}  // namespace hcl_drivers
