// NMT (network management, CiA 301): the master's commands on COB-ID 0 and the nodes'
// heartbeat/boot-up messages on 0x700 + node.
//   command frame: id 0x000, 2 bytes [command, node id (0 = all nodes)]
//   heartbeat:     id 0x700+node, 1 byte [state]; state 0 is the boot-up message
#pragma once

#include <cstdint>
#include <optional>

#include "hcl_drivers/transport/can_frame.h"

namespace hcl_drivers {
namespace canopen {

enum class NmtCommand : uint8_t {
  kStart = 0x01,
  kStop = 0x02,
  kEnterPreOperational = 0x80,
  kResetNode = 0x81,
  kResetCommunication = 0x82,
};

enum class NmtState : uint8_t {
  kBootUp = 0x00,
  kStopped = 0x04,
  kOperational = 0x05,
  kPreOperational = 0x7F,
  kUnknown = 0xFF,  // not seen yet (not on the wire)
};

const char* toString(NmtState s);

transport::CanFrame encodeNmt(NmtCommand cmd, uint8_t node_id);

struct NmtRequest {
  NmtCommand command;
  uint8_t node_id;
};
// Empty for anything but a well-formed NMT command frame.
std::optional<NmtRequest> decodeNmt(const transport::CanFrame& f);

struct Heartbeat {
  uint8_t node_id = 0;
  NmtState state = NmtState::kUnknown;
  bool bootUp() const { return state == NmtState::kBootUp; }
};
transport::CanFrame encodeHeartbeat(uint8_t node_id, NmtState state);
// Empty for anything but a well-formed heartbeat (id 0x701..0x77F, 1 byte, known state).
std::optional<Heartbeat> decodeHeartbeat(const transport::CanFrame& f);

}  // namespace canopen
}  // namespace hcl_drivers
