// CAN motor board (2 H-bridges, 2 quadrature encoders), CANopen node, as the firmware documents it:
//   RPDO1  command_cob_id (0x200+n), 4 bytes: pwm0 i16 LE, pwm1 i16 LE
//          duty in 1/1000 of full voltage, -1000..1000 (the driver's native unit)
//   TPDO1  encoder_cob_id (0x180+n), 8 bytes: encoder0 u32 LE, encoder1 u32 LE (requested by RTR)
//   TPDO2  status_cob_id  (0x280+n), 5 bytes: pwm0 applied i16, pwm1 applied i16, flags u8
//          flags bit0: the watchdog stopped the motors (no RPDO1 for 200 ms)
//   SDO    0x2001:00 u16 watchdog [ms] (rw, default 200), 0x2002:00 u16 firmware version (ro)
#pragma once

#include <array>
#include <optional>

#include "hcl_drivers/canopen/pdo.h"

namespace hcl_drivers {
namespace motor_board {

using canopen::CanFrame;
constexpr int kMotors = 2;
constexpr int16_t kPwmMax = 1000;
constexpr uint16_t kWatchdogIndex = 0x2001;
constexpr uint16_t kVersionIndex = 0x2002;

inline CanFrame encodeCommand(uint32_t cob_id, const std::array<int16_t, kMotors>& pwm) {
  std::vector<uint8_t> b;
  for (int16_t p : pwm) canopen::putU16(b, static_cast<uint16_t>(p < -kPwmMax ? -kPwmMax : (p > kPwmMax ? kPwmMax : p)));
  return canopen::encodePdo(cob_id, b);
}

struct Encoders {
  std::array<uint32_t, kMotors> raw{};
};
inline std::optional<Encoders> decodeEncoders(const CanFrame& f) {
  if (f.rtr || f.error || f.dlc != 8) return std::nullopt;
  return Encoders{{canopen::getU32(f, 0), canopen::getU32(f, 4)}};
}

struct Status {
  std::array<int16_t, kMotors> pwm{};
  bool watchdog_stopped = false;
};
inline std::optional<Status> decodeStatus(const CanFrame& f) {
  if (f.rtr || f.error || f.dlc != 5) return std::nullopt;
  Status s;
  s.pwm = {canopen::getI16(f, 0), canopen::getI16(f, 2)};
  if (s.pwm[0] < -kPwmMax || s.pwm[0] > kPwmMax || s.pwm[1] < -kPwmMax || s.pwm[1] > kPwmMax) return std::nullopt;
  if (f.data[4] & ~0x01) return std::nullopt;
  s.watchdog_stopped = f.data[4] & 0x01;
  return s;
}

}  // namespace motor_board
}  // namespace hcl_drivers
