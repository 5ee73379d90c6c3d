// Register map of the Microchip MCP23016 16-bit I/O expander (datasheet DS20090), 7-bit
// address 0x20..0x27. Registers come in pairs (port 0, port 1); a read or write of one
// register of a pair continues with the other one (the pointer toggles within the pair).
//   0x00/01 GP0/GP1       port value (read: pins; write: output latch)
//   0x02/03 OLAT0/OLAT1   output latch
//   0x04/05 IPOL0/IPOL1   input polarity: 1 = the GP bit reads inverted
//   0x06/07 IODIR0/IODIR1 direction: 1 = input (power-on 0xFF), 0 = output
//   0x08/09 INTCAP0/1     port value captured at the last interrupt (read only)
//   0x0A/0B IOCON0/1      bit0 IARES: interrupt activity resolution
// A 16-bit value here is port 0 in bits 0..7 and port 1 in bits 8..15.
#pragma once

#include <cstdint>
#include <vector>

namespace hcl_drivers {
namespace mcp23016 {

constexpr uint8_t kRegGp0 = 0x00;
constexpr uint8_t kRegOlat0 = 0x02;
constexpr uint8_t kRegIpol0 = 0x04;
constexpr uint8_t kRegIodir0 = 0x06;
constexpr uint8_t kRegIntcap0 = 0x08;
constexpr uint8_t kRegIocon0 = 0x0A;
constexpr uint16_t kIodirPowerOn = 0xFFFF;
constexpr uint8_t kAddressMin = 0x20;
constexpr uint8_t kAddressMax = 0x27;

// The two bytes of a register pair as written on the wire (port 0 first).
inline std::vector<uint8_t> encodePair(uint16_t v) {
  return {static_cast<uint8_t>(v & 0xFF), static_cast<uint8_t>(v >> 8)};
}
inline uint16_t decodePair(const std::vector<uint8_t>& b) {
  return b.size() < 2 ? 0 : static_cast<uint16_t>(b[0] | (b[1] << 8));
}

// Only the pins configured as inputs, as the driver reports them.
inline uint16_t inputBits(uint16_t gp, uint16_t iodir) { return gp & iodir; }

}  // namespace mcp23016
}  // namespace hcl_drivers
