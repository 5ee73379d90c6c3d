#include "hcl_drivers/transport/can_error.h"

#include <algorithm>

namespace hcl_drivers {
namespace transport {

const char* toString(BusState s) {
  switch (s) {
    case BusState::kErrorActive: return "error-active";
    case BusState::kWarning: return "warning";
    case BusState::kErrorPassive: return "error-passive";
    case BusState::kBusOff: return "bus-off";
  }
  return "?";
}

CanErrorEvent decodeErrorFrame(const CanFrame& f) {
  CanErrorEvent e;
  if (!f.error) return e;
  const uint32_t c = f.id;
  const uint8_t ctrl = f.dlc > 1 ? f.data[1] : 0;
  e.bus_off = c & can_err::kBusOff;
  e.restarted = c & can_err::kRestarted;
  e.no_ack = c & can_err::kNoAck;
  e.protocol = (c & can_err::kProtocol) || (c & can_err::kBusError);
  e.tx_timeout = c & can_err::kTxTimeout;
  if (c & can_err::kController) {
    e.passive = ctrl & (can_err::kCtrlRxPassive | can_err::kCtrlTxPassive);
    e.warning = ctrl & (can_err::kCtrlRxWarning | can_err::kCtrlTxWarning);
    e.active = ctrl & can_err::kCtrlActive;
    e.overflow = ctrl & (can_err::kCtrlRxOverflow | can_err::kCtrlTxOverflow);
  }
  if ((c & can_err::kCounters) && f.dlc == 8) {
    e.has_counters = true;
    e.tx_errors = f.data[6];
    e.rx_errors = f.data[7];
  }
  return e;
}

std::string CanErrorEvent::describe() const {
  std::string s;
  auto add = [&s](const char* w) { s += (s.empty() ? "" : ", ") + std::string(w); };
  if (bus_off) add("bus-off");
  if (restarted) add("controller restarted");
  if (passive) add("error-passive");
  if (warning) add("error warning");
  if (active) add("back to error-active");
  if (no_ack) add("no ACK");
  if (protocol) add("protocol/bus error");
  if (tx_timeout) add("TX timeout");
  if (overflow) add("controller overflow");
  return s.empty() ? "error frame" : s;
}

CanFrame makeErrorFrame(uint32_t classes, uint8_t ctrl) {
  CanFrame f;
  f.error = true;
  f.id = classes & can_err::kAll;
  f.dlc = 8;
  f.data[1] = ctrl;
  return f;
}

void CanBusStatus::apply(const CanErrorEvent& e, double now_s) {
  ++error_frames;
  last_error = e.describe();
  if (e.has_counters) {
    tx_errors = e.tx_errors;
    rx_errors = e.rx_errors;
  }
  if (e.bus_off) {
    if (state != BusState::kBusOff) ++bus_off_count;
    state = BusState::kBusOff;
    bus_off_since = now_s;
    return;  // restarted in the same frame is handled by the next one
  }
  if (e.restarted) {
    ++restarts;
    state = BusState::kErrorActive;
  }
  if (e.active && state != BusState::kBusOff) state = BusState::kErrorActive;
  if (e.active && state == BusState::kBusOff) state = BusState::kErrorActive;
  if (e.passive && state != BusState::kBusOff) {
    if (state != BusState::kErrorPassive) ++passive_count;
    state = BusState::kErrorPassive;
  } else if (e.warning && state == BusState::kErrorActive) {
    state = BusState::kWarning;
  }
}

void CanBusStatus::frameReceived(double now_s) {
  ++rx_frames;
  if (state == BusState::kBusOff && now_s - bus_off_since > kBusOffHoldoff) {
    // Receiving means the controller is back on the bus (automatic restart).
    state = BusState::kErrorActive;
    ++restarts;
  }
}

}  // namespace transport
}  // namespace hcl_drivers
