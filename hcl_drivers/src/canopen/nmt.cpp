#include "hcl_drivers/canopen/nmt.h"

#include "hcl_drivers/canopen/cob_id.h"

namespace hcl_drivers {
namespace canopen {

using transport::CanFrame;

const char* toString(NmtState s) {
  switch (s) {
    case NmtState::kBootUp: return "boot-up";
    case NmtState::kStopped: return "stopped";
    case NmtState::kOperational: return "operational";
    case NmtState::kPreOperational: return "pre-operational";
    case NmtState::kUnknown: return "unknown";
  }
  return "unknown";
}

CanFrame encodeNmt(NmtCommand cmd, uint8_t node_id) {
  return CanFrame::make(kNmt, {static_cast<uint8_t>(cmd), static_cast<uint8_t>(node_id & 0x7F)});
}

std::optional<NmtRequest> decodeNmt(const CanFrame& f) {
  if (f.error || f.rtr || f.extended || f.id != kNmt || f.dlc != 2 || f.data[1] > 127) return std::nullopt;
  switch (f.data[0]) {
    case 0x01: case 0x02: case 0x80: case 0x81: case 0x82:
      return NmtRequest{static_cast<NmtCommand>(f.data[0]), f.data[1]};
    default:
      return std::nullopt;
  }
}

CanFrame encodeHeartbeat(uint8_t node_id, NmtState state) {
  return CanFrame::make(kHeartbeat + (node_id & 0x7F), {static_cast<uint8_t>(state)});
}

std::optional<Heartbeat> decodeHeartbeat(const CanFrame& f) {
  if (f.error || f.rtr || f.extended || functionOf(f.id) != kHeartbeat || nodeOf(f.id) == 0 || f.dlc != 1)
    return std::nullopt;
  const uint8_t s = f.data[0] & 0x7F;  // bit 7 is the toggle bit of node guarding
  switch (s) {
    case 0x00: case 0x04: case 0x05: case 0x7F:
      return Heartbeat{nodeOf(f.id), static_cast<NmtState>(s)};
    default:
      return std::nullopt;
  }
}

}  // namespace canopen
}  // namespace hcl_drivers
