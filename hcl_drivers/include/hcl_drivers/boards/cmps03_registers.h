// Register map of the Devantech CMPS03 magnetic compass, I2C mode (datasheet "CMPS03 -
// Robot Compass Module"), fixed 7-bit address 0x60 (0xC0 in 8-bit notation).
//   0x00 software revision
//   0x01 bearing as a byte, 0..255 for a full circle
//   0x02/03 bearing as a word, high byte first, 0..3599 = 0..359.9 degrees
//   0x04..0x0B internal test registers; 0x0C..0x0E unlocking; 0x0F calibrate command
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

namespace hcl_drivers {
namespace cmps03 {

constexpr uint8_t kAddress = 0x60;
constexpr uint8_t kRegRevision = 0x00;
constexpr uint8_t kRegBearingByte = 0x01;
constexpr uint8_t kRegBearingWord = 0x02;
constexpr std::size_t kBlockSize = 4;  // 0x00..0x03
constexpr uint16_t kWordMax = 3599;

struct Reading {
  uint8_t revision = 0;
  uint8_t bearing_byte = 0;
  uint16_t bearing_word = 0;  // tenths of a degree
  double degrees() const { return bearing_word / 10.0; }
};

// The 4 bytes read from 0x00; empty when the size is wrong, the word is beyond 3599, or
// the byte and word bearings disagree by more than 2 byte steps (a torn or garbled read).
inline std::optional<Reading> decodeBlock(const std::vector<uint8_t>& b) {
  if (b.size() != kBlockSize) return std::nullopt;
  Reading r;
  r.revision = b[0];
  r.bearing_byte = b[1];
  r.bearing_word = static_cast<uint16_t>((b[2] << 8) | b[3]);
  if (r.bearing_word > kWordMax) return std::nullopt;
  const int from_word = static_cast<int>(r.bearing_word * 256 / 3600);
  int diff = from_word - r.bearing_byte;
  if (diff < 0) diff = -diff;
  if (diff > 128) diff = 256 - diff;  // wraps at north
  if (diff > 2) return std::nullopt;
  return r;
}

}  // namespace cmps03
}  // namespace hcl_drivers
