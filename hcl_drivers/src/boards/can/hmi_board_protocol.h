// CAN human interface board (2x16 character LCD, 4x4 keypad), CANopen node:
//   RPDO1  lcd_cob_id (0x200+n), 3..8 bytes: line u8 (0..1), column u8 (0..15), 1..6 ASCII characters
//          written at (line, column); characters past column 15 are ignored by the firmware
//   TPDO1  keys_cob_id (0x180+n), 4 bytes: keys u16 LE (bit i = key i held), last key u8 (255 = none),
//          press counter u8 (wraps)                                                       (RTR)
// Keys, by index: 0-9, A, B, C, D, *, # (row-major on the keypad: 1 2 3 A / 4 5 6 B / 7 8 9 C / * 0 # D).
#pragma once

#include <optional>
#include <string>

#include "hcl_drivers/canopen/pdo.h"

namespace hcl_drivers {
namespace hmi_board {

using canopen::CanFrame;
constexpr int kLines = 2;
constexpr int kColumns = 16;
constexpr int kCharsPerFrame = 6;

inline CanFrame encodeLcd(uint32_t cob_id, uint8_t line, uint8_t column, const std::string& text) {
  std::vector<uint8_t> b{line, column};
  for (std::size_t i = 0; i < text.size() && i < kCharsPerFrame; ++i) b.push_back(static_cast<uint8_t>(text[i]));
  return canopen::encodePdo(cob_id, b);
}

struct Keys {
  uint16_t held = 0;
  uint8_t last_key = 255;
  uint8_t presses = 0;
};
inline std::optional<Keys> decodeKeys(const CanFrame& f) {
  if (f.rtr || f.error || f.dlc != 4) return std::nullopt;
  Keys k{canopen::getU16(f, 0), f.data[2], f.data[3]};
  if (k.last_key != 255 && k.last_key > 15) return std::nullopt;
  return k;
}

// Printable ASCII only, padded/cut to 16 columns: what the LCD can show.
inline std::string lcdLine(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (out.size() == kColumns) break;
    out.push_back(c >= 0x20 && c < 0x7F ? c : '?');
  }
  out.resize(kColumns, ' ');
  return out;
}

}  // namespace hmi_board
}  // namespace hcl_drivers
