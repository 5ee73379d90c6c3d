#include "hal_nodes/devices/odometry/encoder_tracker.h"

namespace hal_nodes {

int64_t wrappedDelta(uint32_t from, uint32_t to, uint8_t bits) {
  const uint64_t modulus = uint64_t{1} << bits;
  const uint64_t d = (static_cast<uint64_t>(to) - static_cast<uint64_t>(from)) & (modulus - 1);
  return d >= modulus / 2 ? static_cast<int64_t>(d) - static_cast<int64_t>(modulus) : static_cast<int64_t>(d);
}

int64_t EncoderTracker::update(uint32_t raw, uint8_t bits, uint32_t board_resets, Event* event) {
  Event ev = Event::kNone;
  int64_t delta = 0;
  if (bits == 0 || bits > 32) {
    ev = Event::kBadWidth;  // not a counter we can unwrap: keep the old baseline
  } else if (!has_baseline_ || bits != bits_) {
    ev = Event::kBaseline;
  } else if (board_resets != resets_) {
    ev = Event::kBoardReset;
  } else {
    delta = wrappedDelta(raw_, raw, bits);
  }
  if (ev != Event::kBadWidth) {
    has_baseline_ = true;
    raw_ = raw;
    bits_ = bits;
    resets_ = board_resets;
  }
  if (event) *event = ev;
  return delta;
}

}  // namespace hal_nodes
