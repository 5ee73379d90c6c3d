// Register map of Logion's HBmotor board: one H-bridge (one motor) and its quadrature
// encoder counter behind an I2C slave (AVR firmware of the original robot, 7-bit address
// 0x10..0x17 by jumpers). The original firmware's source is not available; this map is the
// documented reconstruction our driver and emulator both follow (docs: this file).
//
//   reg  name       access  meaning
//   0x00 VERSION    R       firmware version (0x12 = 1.2)
//   0x01 STATUS     R       bit0 motor driven (command != 0), bit1 over-current,
//                           bit2 watchdog tripped (command forced to 0), bit7 power-on flag
//                           (set at reset, cleared by CONTROL bit0)
//   0x02 COMMAND    R/W     signed PWM duty, int8 -127..127 (-128 is invalid, read as -127)
//   0x03 CONTROL    W       bit0: clear power-on flag; bit1: zero the encoder counter
//   0x04 ENCODER    R       encoder counter, uint32 little-endian 0x04..0x07, latched when
//                           0x04 is addressed, so one combined read is consistent
//   0x08 WATCHDOG   R/W     firmware watchdog [10 ms units], 1..255; 0 = off. With no COMMAND
//                           write for that long the firmware stops the motor by itself.
//
// The register pointer auto-increments on every byte read or written.
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>
#include <vector>

namespace hcl_drivers {
namespace hbmotor {

constexpr uint8_t kRegVersion = 0x00;
constexpr uint8_t kRegStatus = 0x01;
constexpr uint8_t kRegCommand = 0x02;
constexpr uint8_t kRegControl = 0x03;
constexpr uint8_t kRegEncoder = 0x04;
constexpr uint8_t kRegWatchdog = 0x08;
constexpr std::size_t kBlockSize = 9;  // 0x00..0x08 in one read

constexpr uint8_t kStatusDriven = 0x01;
constexpr uint8_t kStatusOverCurrent = 0x02;
constexpr uint8_t kStatusWatchdog = 0x04;
constexpr uint8_t kStatusPowerOn = 0x80;
constexpr uint8_t kControlClearPowerOn = 0x01;
constexpr uint8_t kControlZeroEncoder = 0x02;
constexpr int kCommandMax = 127;

struct Block {
  uint8_t version = 0;
  uint8_t status = 0;
  int8_t command = 0;
  uint32_t encoder = 0;
  uint8_t watchdog = 0;
};

// The 9 bytes read from 0x00; empty when the size is wrong or a reserved status bit is set
// (bits 3..6 are always 0: a set one means the bytes are not from an HBmotor).
inline std::optional<Block> decodeBlock(const std::vector<uint8_t>& b) {
  if (b.size() != kBlockSize || (b[1] & 0x78) != 0) return std::nullopt;
  Block k;
  k.version = b[0];
  k.status = b[1];
  k.command = static_cast<int8_t>(b[2]);
  k.encoder = static_cast<uint32_t>(b[4]) | (static_cast<uint32_t>(b[5]) << 8) | (static_cast<uint32_t>(b[6]) << 16) |
              (static_cast<uint32_t>(b[7]) << 24);
  k.watchdog = b[8];
  return k;
}

// The COMMAND byte for a requested duty: clamped to -127..127.
inline uint8_t encodeCommand(int32_t duty) {
  return static_cast<uint8_t>(static_cast<int8_t>(std::clamp<int32_t>(duty, -kCommandMax, kCommandMax)));
}

// WATCHDOG register value for a timeout in seconds (0 = off), rounded up, 1..255.
inline uint8_t encodeWatchdog(double seconds) {
  if (seconds <= 0.0) return 0;
  const double ticks = seconds * 100.0;
  return static_cast<uint8_t>(std::clamp(static_cast<int>(ticks + 0.999), 1, 255));
}

}  // namespace hbmotor
}  // namespace hcl_drivers
