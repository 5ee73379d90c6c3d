// Register map of the Devantech SRF02 ultrasonic ranger, I2C mode (datasheet "SRF02
// Ultrasonic range finder, Technical Specification"), 7-bit address 0x70..0x7F (0xE0..0xFE
// in the datasheet's 8-bit notation).
//   write 0x00  command: 0x50 range in inches, 0x51 in cm, 0x52 in microseconds,
//               0x56..0x58 fake ranging (no burst), 0x5C burst only, 0x60 force autotune restart
//   read  0x00  software revision; reads 0xFF while ranging (the SRF02 does not drive SDA
//               during the ~65 ms conversion, the pull-up makes it 0xFF)
//         0x01  unused (reads 0x80)
//         0x02/03 range, high byte first, in the unit of the last command
//         0x04/05 autotune minimum range, high byte first
// Range is 16..600 cm; closer than ~15 cm cannot be measured.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

namespace hcl_drivers {
namespace srf02 {

constexpr uint8_t kRegCommand = 0x00;
constexpr uint8_t kRegRevision = 0x00;
constexpr uint8_t kCmdRangeInches = 0x50;
constexpr uint8_t kCmdRangeCm = 0x51;
constexpr uint8_t kCmdRangeUs = 0x52;
constexpr uint8_t kBusy = 0xFF;
constexpr double kConversionTime = 0.065;  // [s] datasheet: allow 65 ms per ranging
constexpr double kMinRangeM = 0.16;
constexpr double kMaxRangeM = 6.0;
constexpr double kFieldOfView = 0.96;       // [rad] ~55 degrees full beam width
constexpr uint8_t kAddressMin = 0x70;
constexpr uint8_t kAddressMax = 0x7F;
constexpr std::size_t kResultSize = 4;      // 0x00..0x03

enum class ResultKind { kBusy, kRange, kInvalid };
struct Result {
  ResultKind kind = ResultKind::kInvalid;
  uint8_t revision = 0;
  uint16_t range_cm = 0;
};

// The 4 bytes read from 0x00 after a cm ranging: busy while the revision reads 0xFF,
// invalid when the size is wrong or the range is beyond 16 m (not from an SRF02).
inline Result decodeResult(const std::vector<uint8_t>& b) {
  Result r;
  if (b.size() != kResultSize) return r;
  r.revision = b[0];
  if (b[0] == kBusy) {
    r.kind = ResultKind::kBusy;
    return r;
  }
  r.range_cm = static_cast<uint16_t>((b[2] << 8) | b[3]);
  r.kind = r.range_cm > 1600 ? ResultKind::kInvalid : ResultKind::kRange;
  return r;
}

inline double centimetresToMetres(uint16_t cm) { return cm / 100.0; }

}  // namespace srf02
}  // namespace hcl_drivers
