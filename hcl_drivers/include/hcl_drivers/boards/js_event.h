// The Linux joystick API's event record (linux/joystick.h, struct js_event, 8 bytes in host
// byte order) and a model of the stick it describes. Pure code, no I/O: the driver feeds the
// bytes it read; tests feed bytes they made.
//   u32 time [ms]   s16 value   u8 type (0x01 button, 0x02 axis, | 0x80 init)   u8 number
// On open the kernel sends one init event per button and axis with its current state.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hcl_drivers {
namespace js {

constexpr uint8_t kButton = 0x01;
constexpr uint8_t kAxis = 0x02;
constexpr uint8_t kInit = 0x80;
constexpr std::size_t kEventSize = 8;
constexpr std::size_t kMaxAxes = 64;     // ABS_CNT
constexpr std::size_t kMaxButtons = 512;  // KEY_MAX - BTN_MISC + 1

struct Event {
  uint32_t time_ms = 0;
  int16_t value = 0;
  uint8_t type = 0;
  uint8_t number = 0;
};

// Axis value -32767..32767 to -1..1 with a deadzone: |v| < deadzone reads 0, and the rest of
// the travel is rescaled so the output is continuous and still reaches +-1.
double applyDeadzone(int16_t raw, double deadzone);

// Splits a byte stream into events; keeps a partial record for the next feed.
class Decoder {
 public:
  void feed(const uint8_t* data, std::size_t n, std::vector<Event>& out);
  void reset() { partial_.clear(); }

 private:
  std::vector<uint8_t> partial_;
};

// The stick's current state from its events. Arrays grow to the highest number seen (or
// start at the sizes the device reports with JSIOCGAXES / JSIOCGBUTTONS).
class State {
 public:
  void resize(std::size_t axes, std::size_t buttons);
  // Returns false (and changes nothing) for an unknown type or an out-of-range number.
  bool apply(const Event& e);
  void clear();  // everything released and centred (device gone)
  const std::vector<int16_t>& axes() const { return axes_; }
  const std::vector<uint8_t>& buttons() const { return buttons_; }

 private:
  std::vector<int16_t> axes_;
  std::vector<uint8_t> buttons_;
};

}  // namespace js
}  // namespace hcl_drivers
