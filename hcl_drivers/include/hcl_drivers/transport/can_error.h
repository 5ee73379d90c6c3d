// Decoding of CAN error frames (SocketCAN's linux/can/error.h layout, also carried by the
// CAN-over-UDP bus) and the bus state they imply: error-active, warning, error-passive, bus-off.
// A bus-off bus refuses every exchange until the controller restarts (CAN_ERR_RESTARTED),
// reports error-active again, or a frame is received well after the bus-off (a bus-off
// controller receives nothing; frames already in flight when it happened do not count).
#pragma once

#include <cstdint>
#include <string>

#include "hcl_drivers/transport/can_frame.h"

namespace hcl_drivers {
namespace transport {

// Error class bits of an error frame's id (linux/can/error.h values).
namespace can_err {
constexpr uint32_t kTxTimeout = 0x001;
constexpr uint32_t kLostArbitration = 0x002;
constexpr uint32_t kController = 0x004;  // details in data[1]
constexpr uint32_t kProtocol = 0x008;
constexpr uint32_t kTransceiver = 0x010;
constexpr uint32_t kNoAck = 0x020;
constexpr uint32_t kBusOff = 0x040;
constexpr uint32_t kBusError = 0x080;
constexpr uint32_t kRestarted = 0x100;
constexpr uint32_t kCounters = 0x200;  // data[6]/data[7] hold tx/rx error counters
// data[1] controller status bits
constexpr uint8_t kCtrlRxOverflow = 0x01;
constexpr uint8_t kCtrlTxOverflow = 0x02;
constexpr uint8_t kCtrlRxWarning = 0x04;
constexpr uint8_t kCtrlTxWarning = 0x08;
constexpr uint8_t kCtrlRxPassive = 0x10;
constexpr uint8_t kCtrlTxPassive = 0x20;
constexpr uint8_t kCtrlActive = 0x40;
constexpr uint32_t kAll = 0x1FFFFFFF;
}  // namespace can_err

enum class BusState : uint8_t { kErrorActive = 0, kWarning = 1, kErrorPassive = 2, kBusOff = 3 };
const char* toString(BusState s);

// What one error frame says.
struct CanErrorEvent {
  bool bus_off = false;
  bool restarted = false;
  bool passive = false;    // rx or tx error-passive
  bool warning = false;    // rx or tx warning level
  bool active = false;     // back to error-active
  bool no_ack = false;
  bool protocol = false;
  bool tx_timeout = false;
  bool overflow = false;
  bool has_counters = false;
  uint8_t tx_errors = 0;
  uint8_t rx_errors = 0;
  std::string describe() const;
};

// Empty-event for a non-error frame; never throws, whatever the bytes.
CanErrorEvent decodeErrorFrame(const CanFrame& f);

// An error frame for fault injection and tests (what a controller would report).
CanFrame makeErrorFrame(uint32_t classes, uint8_t ctrl = 0);

// The bus state machine driven by error events and received frames.
struct CanBusStatus {
  BusState state = BusState::kErrorActive;
  unsigned long error_frames = 0;
  unsigned long bus_off_count = 0;
  unsigned long restarts = 0;
  unsigned long passive_count = 0;
  unsigned long rx_frames = 0;
  unsigned long tx_frames = 0;
  unsigned long tx_failures = 0;
  unsigned long malformed = 0;   // transport-level garbage (bad UDP datagrams, short reads)
  unsigned long overruns = 0;    // frames dropped because a receiver's queue was full
  uint8_t tx_errors = 0;
  uint8_t rx_errors = 0;
  std::string last_error;
  double bus_off_since = 0.0;   // [s] monotonic time of the last bus-off

  static constexpr double kBusOffHoldoff = 0.5;  // [s]
  void apply(const CanErrorEvent& e, double now_s = 0.0);
  // A data frame arrived at now_s: more than kBusOffHoldoff after a bus-off it proves the
  // controller is back on the bus.
  void frameReceived(double now_s = 1e300);
};

}  // namespace transport
}  // namespace hcl_drivers
