// Turns a board's raw encoder counter (hcl_drivers/EncoderCounter) into tick increments:
// unwraps the counter modulo 2^bits and re-baselines when the board was reset (the firmware
// restarted its counter) or the counter width changed. The motion between the last sample
// before a reset and the reset itself is unknown: dropping it (a few ms at most) is better
// than guessing from a counter whose restart value we cannot see.
#pragma once

#include <cstdint>

namespace hal_nodes {

class EncoderTracker {
 public:
  enum class Event { kNone, kBaseline, kBoardReset, kBadWidth };

  // Feed one counter sample; returns the signed tick increment since the previous sample
  // (0 when this sample only sets the baseline). Increments of half the counter range or
  // more are indistinguishable from a wrap the other way: poll faster than that.
  int64_t update(uint32_t raw, uint8_t bits, uint32_t board_resets, Event* event = nullptr);

  // The next sample only sets the baseline (e.g. after the encoder was out of use).
  void rebaseline() { has_baseline_ = false; }
  bool hasBaseline() const { return has_baseline_; }

 private:
  bool has_baseline_ = false;
  uint32_t raw_ = 0;
  uint8_t bits_ = 0;
  uint32_t resets_ = 0;
};

// Signed difference of two counter values modulo 2^bits (bits 1..32).
int64_t wrappedDelta(uint32_t from, uint32_t to, uint8_t bits);

}  // namespace hal_nodes
