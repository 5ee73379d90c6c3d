// One classical CAN 2.0 frame, independent of the transport (SocketCAN, CAN over UDP).
// Error frames follow SocketCAN's convention (linux/can/error.h): `error` set, `id` holds the
// error class bits and `data` the details, so both transports decode them with one function.
#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace hcl_drivers {
namespace transport {

struct CanFrame {
  uint32_t id = 0;         // 11-bit (standard) or 29-bit (extended) identifier, no flag bits
  bool extended = false;   // 29-bit identifier
  bool rtr = false;        // remote transmission request (no data, dlc = requested length)
  bool error = false;      // error frame (see can_error.h)
  uint8_t dlc = 0;         // 0..8
  std::array<uint8_t, 8> data{};
  // When the frame reached this process's socket, wall clock [s] (the kernel's receive
  // timestamp, as candump's): 0 for a frame made here. Not part of the frame's identity.
  double received = 0.0;

  static CanFrame make(uint32_t id, std::initializer_list<uint8_t> bytes) {
    CanFrame f;
    f.id = id;
    for (uint8_t b : bytes) {
      if (f.dlc == 8) break;
      f.data[f.dlc++] = b;
    }
    return f;
  }
  static CanFrame remote(uint32_t id, uint8_t dlc) {
    CanFrame f;
    f.id = id;
    f.rtr = true;
    f.dlc = dlc > 8 ? 8 : dlc;
    return f;
  }
  bool operator==(const CanFrame& o) const;
  bool operator!=(const CanFrame& o) const { return !(*this == o); }
};

// Accepts a frame when (frame.id & mask) == (id & mask) and the frame is a data/remote frame
// of the same format (standard/extended). Error frames never match a filter.
struct CanFilter {
  uint32_t id = 0;
  uint32_t mask = 0x7FF;
  bool extended = false;
  bool matches(const CanFrame& f) const {
    return !f.error && f.extended == extended && (f.id & mask) == (id & mask);
  }
};

// candump's compact form: "181#0102AB", "701#R1" (RTR), "12345678#00" (extended), "ERR#..." .
std::string toString(const CanFrame& f);

}  // namespace transport
}  // namespace hcl_drivers
