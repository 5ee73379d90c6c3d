#include "hcl_drivers/transport/socketcan_bus.h"

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <system_error>

#include "receive_timestamp.h"

namespace hcl_drivers {
namespace transport {

namespace {

double monotonicS() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

static_assert(can_err::kBusOff == CAN_ERR_BUSOFF && can_err::kRestarted == CAN_ERR_RESTARTED &&
                  can_err::kController == CAN_ERR_CRTL && can_err::kCtrlActive == CAN_ERR_CRTL_ACTIVE &&
                  can_err::kCtrlTxPassive == CAN_ERR_CRTL_TX_PASSIVE,
              "can_error.h must mirror linux/can/error.h");

int openRaw(int ifindex, const std::string& iface) {
  const int fd = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
  if (fd < 0)
    throw std::system_error(errno, std::generic_category(),
                            "socket(PF_CAN, SOCK_RAW, CAN_RAW) for " + iface + " (does this kernel have AF_CAN?)");
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifindex;
  enableReceiveTimestamps(fd);  // CanFrame::received
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
    const int err = errno;
    ::close(fd);
    throw std::system_error(err, std::generic_category(), "bind CAN socket to " + iface);
  }
  return fd;
}

can_frame toKernel(const CanFrame& f) {
  can_frame k{};
  k.can_id = f.id & (f.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
  if (f.extended) k.can_id |= CAN_EFF_FLAG;
  if (f.rtr) k.can_id |= CAN_RTR_FLAG;
  if (f.error) k.can_id = (f.id & CAN_ERR_MASK) | CAN_ERR_FLAG;
  k.can_dlc = f.dlc > 8 ? 8 : f.dlc;
  if (!f.rtr) std::memcpy(k.data, f.data.data(), k.can_dlc);
  return k;
}

CanFrame fromKernel(const can_frame& k) {
  CanFrame f;
  f.error = k.can_id & CAN_ERR_FLAG;
  f.extended = !f.error && (k.can_id & CAN_EFF_FLAG);
  f.rtr = !f.error && (k.can_id & CAN_RTR_FLAG);
  f.id = f.error ? (k.can_id & CAN_ERR_MASK) : (k.can_id & (f.extended ? CAN_EFF_MASK : CAN_SFF_MASK));
  f.dlc = k.can_dlc > 8 ? 8 : k.can_dlc;
  if (!f.rtr) std::memcpy(f.data.data(), k.data, f.dlc);
  return f;
}

class SocketCanChannel : public CanChannel {
 public:
  SocketCanChannel(std::shared_ptr<SocketCanBus> bus, int fd) : bus_(std::move(bus)), fd_(fd) {}
  ~SocketCanChannel() override { ::close(fd_); }

  bool send(const CanFrame& f) override {
    if (bus_->status().state == BusState::kBusOff && !f.error) {
      last_error_ = "bus-off: " + bus_->status().last_error;
      bus_->noteTx(false, last_error_);
      return false;
    }
    const can_frame k = toKernel(f);
    const ssize_t n = ::write(fd_, &k, sizeof(k));
    if (n != static_cast<ssize_t>(sizeof(k))) {
      // ENOBUFS: the TX queue is full (nobody ACKs); ENETDOWN: the interface is down.
      last_error_ = std::string("write: ") + std::strerror(errno);
      bus_->noteTx(false, last_error_);
      return false;
    }
    bus_->noteTx(true, "");
    return true;
  }

  bool receive(CanFrame& f, double timeout_s) override {
    pollfd p{fd_, POLLIN, 0};
    const int ms = timeout_s > 0 ? static_cast<int>(std::ceil(timeout_s * 1e3)) : 0;
    const int r = ::poll(&p, 1, ms);
    if (r == 0) {
      last_error_ = "timeout";
      return false;
    }
    if (r < 0) {
      last_error_ = std::string("poll: ") + std::strerror(errno);
      return false;
    }
    can_frame k{};
    double received = 0.0;
    const ssize_t n = receiveStamped(fd_, &k, sizeof(k), 0, &received);
    if (n != static_cast<ssize_t>(sizeof(k))) {
      last_error_ = n < 0 ? std::string("recvmsg: ") + std::strerror(errno) : "short read";
      return false;
    }
    f = fromKernel(k);
    f.received = received;
    bus_->noteRx();
    return true;
  }

  void drain() override {
    can_frame k{};
    while (::recv(fd_, &k, sizeof(k), MSG_DONTWAIT) > 0) {
    }
  }

 private:
  std::shared_ptr<SocketCanBus> bus_;
  int fd_;
};

}  // namespace

SocketCanBus::SocketCanBus(const std::string& iface) : CanBus("socketcan://" + iface), iface_(iface) {
  ifindex_ = static_cast<int>(::if_nametoindex(iface.c_str()));
  // Open a socket first: on a kernel without AF_CAN that is the error worth reporting.
  error_fd_ = openRaw(0, iface);
  ::close(error_fd_);
  error_fd_ = -1;
  if (ifindex_ == 0) throw std::system_error(ENODEV, std::generic_category(), "no CAN interface '" + iface + "'");
  error_fd_ = openRaw(ifindex_, iface);
  // The monitor socket takes error frames only: no data filters, every error class.
  ::setsockopt(error_fd_, SOL_CAN_RAW, CAN_RAW_FILTER, nullptr, 0);
  can_err_mask_t mask = CAN_ERR_MASK;
  ::setsockopt(error_fd_, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &mask, sizeof(mask));
  monitor_thread_ = std::thread([this] { monitor(); });
}

SocketCanBus::~SocketCanBus() {
  running_ = false;
  if (monitor_thread_.joinable()) monitor_thread_.join();
  if (error_fd_ >= 0) ::close(error_fd_);
}

std::shared_ptr<CanChannel> SocketCanBus::open(const std::vector<CanFilter>& filters) {
  const int fd = openRaw(ifindex_, iface_);
  std::vector<can_filter> k;
  for (const auto& f : filters) {
    can_filter cf{};
    cf.can_id = f.id | (f.extended ? CAN_EFF_FLAG : 0);
    cf.can_mask = f.mask | CAN_EFF_FLAG;  // never mix standard and extended ids
    k.push_back(cf);
  }
  if (!k.empty() &&
      ::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, k.data(), static_cast<socklen_t>(k.size() * sizeof(can_filter))) != 0) {
    const int err = errno;
    ::close(fd);
    throw std::system_error(err, std::generic_category(), "CAN_RAW_FILTER on " + iface_);
  }
  return std::make_shared<SocketCanChannel>(shared_from_this(), fd);
}

void SocketCanBus::noteTx(bool ok, const std::string& error) {
  std::lock_guard<std::mutex> lk(status_mutex_);
  if (ok) {
    ++status_.tx_frames;
  } else {
    ++status_.tx_failures;
    if (status_.state != BusState::kBusOff) status_.last_error = error;
  }
}

void SocketCanBus::noteRx() {
  std::lock_guard<std::mutex> lk(status_mutex_);
  status_.frameReceived(monotonicS());
}

void SocketCanBus::monitor() {
  while (running_) {
    pollfd p{error_fd_, POLLIN, 0};
    if (::poll(&p, 1, 100) <= 0) continue;
    can_frame k{};
    const ssize_t n = ::read(error_fd_, &k, sizeof(k));
    if (n != static_cast<ssize_t>(sizeof(k))) continue;
    const CanFrame f = fromKernel(k);
    if (!f.error) continue;
    std::lock_guard<std::mutex> lk(status_mutex_);
    status_.apply(decodeErrorFrame(f), monotonicS());
  }
}

}  // namespace transport
}  // namespace hcl_drivers
