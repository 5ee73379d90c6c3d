// SocketCAN: one raw socket per channel with the channel's receive filters set in the
// kernel (CAN_RAW_FILTER), so several boards share `can0` without stealing frames; one more
// raw socket receives error frames only (CAN_RAW_ERR_FILTER) and decodes them into the bus
// state (bus-off, error-passive, controller restarts) on a small monitor thread.
#pragma once

#include <atomic>
#include <thread>

#include "hcl_drivers/transport/can_bus.h"

namespace hcl_drivers {
namespace transport {

class SocketCanBus : public CanBus, public std::enable_shared_from_this<SocketCanBus> {
 public:
  // Throws std::system_error when the interface does not exist or the kernel has no AF_CAN.
  explicit SocketCanBus(const std::string& iface);
  ~SocketCanBus() override;
  std::shared_ptr<CanChannel> open(const std::vector<CanFilter>& filters) override;

  // Called by channels.
  void noteTx(bool ok, const std::string& error);
  void noteRx();

 private:
  void monitor();
  std::string iface_;
  int ifindex_ = 0;
  int error_fd_ = -1;
  std::atomic<bool> running_{true};
  std::thread monitor_thread_;
};

}  // namespace transport
}  // namespace hcl_drivers
