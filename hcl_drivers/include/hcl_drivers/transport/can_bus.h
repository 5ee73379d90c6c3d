// The CAN bus interface. One CanBus object per bus URL and process (openCanBus() shares it),
// and one CanChannel per user (a board driver, an emulator): a channel receives the frames
// matching its own filters, never steals frames from another channel, and does not see the
// frames it sent itself (SocketCAN's default), exactly like one raw socket per board.
//
// URLs: socketcan://IFACE (socketcan_bus.h) and udp://127.0.0.1:PORT (udp_can_bus.h).
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "hcl_drivers/transport/can_error.h"
#include "hcl_drivers/transport/can_frame.h"

namespace hcl_drivers {
namespace transport {

class CanChannel {
 public:
  virtual ~CanChannel() = default;
  // Queues one frame on the bus. False (reason in lastError()) when the bus refused it.
  virtual bool send(const CanFrame& f) = 0;
  // Waits up to timeout_s for one frame matching this channel's filters.
  // False on timeout or error (reason in lastError()).
  virtual bool receive(CanFrame& f, double timeout_s) = 0;
  // Drops the frames already queued for this channel.
  virtual void drain() = 0;
  const std::string& lastError() const { return last_error_; }

 protected:
  std::string last_error_;
};

class CanBus {
 public:
  virtual ~CanBus() = default;
  // A new receiver with its own filters (empty: every data/remote frame).
  virtual std::shared_ptr<CanChannel> open(const std::vector<CanFilter>& filters) = 0;
  // A copy of the bus state and counters (error frames decoded, bus-off, ...).
  CanBusStatus status() const {
    std::lock_guard<std::mutex> lk(status_mutex_);
    return status_;
  }
  const std::string& url() const { return url_; }

 protected:
  explicit CanBus(std::string url) : url_(std::move(url)) {}
  mutable std::mutex status_mutex_;
  CanBusStatus status_;
  std::string url_;
};

// The process-wide bus for `url`, created on first use and shared while anyone holds it.
// Throws std::invalid_argument for a malformed URL and std::system_error/std::runtime_error
// when the bus cannot be opened (no such interface, no AF_CAN, ...).
std::shared_ptr<CanBus> openCanBus(const std::string& url);

}  // namespace transport
}  // namespace hcl_drivers
