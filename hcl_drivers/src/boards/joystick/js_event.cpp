#include "hcl_drivers/boards/js_event.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace hcl_drivers {
namespace js {

double applyDeadzone(int16_t raw, double deadzone) {
  const double v = std::clamp(raw / 32767.0, -1.0, 1.0);
  const double a = std::fabs(v);
  if (a < deadzone) return 0.0;
  if (deadzone >= 1.0) return 0.0;
  return std::copysign((a - deadzone) / (1.0 - deadzone), v);
}

void Decoder::feed(const uint8_t* data, std::size_t n, std::vector<Event>& out) {
  partial_.insert(partial_.end(), data, data + n);
  std::size_t at = 0;
  for (; at + kEventSize <= partial_.size(); at += kEventSize) {
    const uint8_t* p = partial_.data() + at;
    Event e;
    std::memcpy(&e.time_ms, p, 4);  // host byte order, as the kernel writes it
    std::memcpy(&e.value, p + 4, 2);
    e.type = p[6];
    e.number = p[7];
    out.push_back(e);
  }
  partial_.erase(partial_.begin(), partial_.begin() + static_cast<std::ptrdiff_t>(at));
}

void State::resize(std::size_t axes, std::size_t buttons) {
  axes_.resize(std::min(axes, kMaxAxes), 0);
  buttons_.resize(std::min(buttons, kMaxButtons), 0);
}

bool State::apply(const Event& e) {
  const uint8_t type = e.type & static_cast<uint8_t>(~kInit);
  if (type == kAxis) {
    if (e.number >= kMaxAxes) return false;
    if (e.number >= axes_.size()) axes_.resize(e.number + 1u, 0);
    axes_[e.number] = e.value == -32768 ? static_cast<int16_t>(-32767) : e.value;
    return true;
  }
  if (type == kButton) {
    if (e.number >= kMaxButtons || (e.value != 0 && e.value != 1)) return false;
    if (e.number >= buttons_.size()) buttons_.resize(e.number + 1u, 0);
    buttons_[e.number] = static_cast<uint8_t>(e.value);
    return true;
  }
  return false;
}

void State::clear() {
  std::fill(axes_.begin(), axes_.end(), 0);
  std::fill(buttons_.begin(), buttons_.end(), 0);
}

}  // namespace js
}  // namespace hcl_drivers
