// CAN servo board (4 RC servos, 4 ADC inputs for SHARP GP2D12 rangers, 16 switches), CANopen node:
//   RPDO1  servo_cob_id  (0x200+n), 8 bytes: pulse0..3 u16 LE [us], 500..2500, 0 = no pulses (servo limp)
//   TPDO1  ranger_cob_id (0x180+n), 8 bytes: adc0..3 u16 LE, 10-bit (0..1023), 5 V reference (RTR)
//   TPDO2  switch_cob_id (0x280+n), 2 bytes: switches u16 LE, bit i = switch i closed (RTR)
//
// SHARP GP2D12 (datasheet, typical output voltage vs distance to a white target):
//   10 cm 2.40 V, 15 cm 1.65 V, 20 cm 1.30 V, 25 cm 1.08 V, 30 cm 0.92 V, 40 cm 0.73 V,
//   50 cm 0.60 V, 60 cm 0.51 V, 70 cm 0.45 V, 80 cm 0.40 V (range 10..80 cm).
// Output above 2.45 V is the ambiguous near zone (< 10 cm): -inf (REP 117); below 0.38 V nothing
// is in range: +inf.
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "hcl_drivers/canopen/pdo.h"

namespace hcl_drivers {
namespace servo_board {

using canopen::CanFrame;
constexpr int kServos = 4;
constexpr int kAdcs = 4;
constexpr uint16_t kPulseMin = 500, kPulseMax = 2500;
constexpr double kAdcRef = 5.0;
constexpr double kMinRange = 0.10, kMaxRange = 0.80;

inline CanFrame encodeServos(uint32_t cob_id, const std::array<uint16_t, kServos>& pulse) {
  std::vector<uint8_t> b;
  for (uint16_t p : pulse) canopen::putU16(b, p);
  return canopen::encodePdo(cob_id, b);
}
inline bool validPulse(int p) { return p == 0 || (p >= kPulseMin && p <= kPulseMax); }

inline std::optional<std::array<uint16_t, kAdcs>> decodeRangers(const CanFrame& f) {
  if (f.rtr || f.error || f.dlc != 8) return std::nullopt;
  std::array<uint16_t, kAdcs> a{};
  for (int i = 0; i < kAdcs; ++i) {
    a[i] = canopen::getU16(f, 2 * i);
    if (a[i] > 1023) return std::nullopt;
  }
  return a;
}

inline std::optional<uint16_t> decodeSwitches(const CanFrame& f) {
  if (f.rtr || f.error || f.dlc != 2) return std::nullopt;
  return canopen::getU16(f, 0);
}

// GP2D12 curve: the driver inverts it by linear interpolation between datasheet points.
inline double gp2d12Metres(uint16_t adc) {
  static const double kDist[] = {0.10, 0.15, 0.20, 0.25, 0.30, 0.40, 0.50, 0.60, 0.70, 0.80};
  static const double kVolt[] = {2.40, 1.65, 1.30, 1.08, 0.92, 0.73, 0.60, 0.51, 0.45, 0.40};
  const double v = adc * kAdcRef / 1023.0;
  if (v > 2.45) return -std::numeric_limits<double>::infinity();
  if (v < 0.38) return std::numeric_limits<double>::infinity();
  if (v >= kVolt[0]) return kDist[0];
  if (v <= kVolt[9]) return kDist[9];
  for (int i = 0; i < 9; ++i)
    if (v <= kVolt[i] && v >= kVolt[i + 1])
      return kDist[i] + (kDist[i + 1] - kDist[i]) * (kVolt[i] - v) / (kVolt[i] - kVolt[i + 1]);
  return std::numeric_limits<double>::infinity();
}

}  // namespace servo_board
}  // namespace hcl_drivers
