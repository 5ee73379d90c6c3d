// CAN stepper board (2 steppers, 2 end switches each), CANopen node:
//   RPDO1  target_cob_id   (0x200+n), 8 bytes: target0 i32 LE, target1 i32 LE [steps]
//   TPDO1  position_cob_id (0x180+n), 8 bytes: position0 i32 LE, position1 i32 LE [steps] (RTR)
//   TPDO2  switch_cob_id   (0x280+n), 2 bytes: end switches u8 (bit 2i min, 2i+1 max of stepper i),
//          moving u8 (bit i)
// The firmware moves each stepper towards its target and stops at an end switch in that direction.
#pragma once

#include <array>
#include <optional>

#include "hcl_drivers/canopen/pdo.h"

namespace hcl_drivers {
namespace stepper_board {

using canopen::CanFrame;
constexpr int kSteppers = 2;

inline CanFrame encodeTargets(uint32_t cob_id, const std::array<int32_t, kSteppers>& t) {
  std::vector<uint8_t> b;
  for (int32_t v : t) canopen::putU32(b, static_cast<uint32_t>(v));
  return canopen::encodePdo(cob_id, b);
}

inline std::optional<std::array<int32_t, kSteppers>> decodePositions(const CanFrame& f) {
  if (f.rtr || f.error || f.dlc != 8) return std::nullopt;
  return std::array<int32_t, kSteppers>{canopen::getI32(f, 0), canopen::getI32(f, 4)};
}

struct Switches {
  uint8_t end_switches = 0;
  uint8_t moving = 0;
};
inline std::optional<Switches> decodeSwitches(const CanFrame& f) {
  if (f.rtr || f.error || f.dlc != 2 || (f.data[0] & 0xF0) || (f.data[1] & 0xFC)) return std::nullopt;
  return Switches{f.data[0], f.data[1]};
}

}  // namespace stepper_board
}  // namespace hcl_drivers
