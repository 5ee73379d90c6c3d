#include "robot_core/loop_pacer.h"

#include <algorithm>
#include <limits>

namespace robot_core {

double LoopPacer::tokensAt(double t) const {
  return std::min(kBurst, tokens_ + (t - ran_at_) / min_interval_);
}

double LoopPacer::next() const {
  if (!started_) return -std::numeric_limits<double>::infinity();
  if (woken_) return ran_at_ + std::max(0.0, 1.0 - tokens_) * min_interval_;  // as soon as a token is there
  return last_ + period_ * (patient_ ? 1.0 + kPatience : 1.0);
}

void LoopPacer::ran(double now) {
  if (!started_) {
    started_ = true;
    last_ = ran_at_ = now;
    tokens_ = kBurst - 1.0;
    woken_ = false;
    return;
  }
  const double scheduled = next();
  // An unwoken run that is on time (a tick up to half a period early, or less than a period
  // late) counts at its scheduled time, so a plain periodic loop keeps its rate exactly however
  // its runs jitter; a woken run sets a new phase.
  const bool on_schedule = !woken_ && now >= scheduled - 0.5 * period_ && now - scheduled < period_;
  // A tick the patience postponed still counts in its own slot: the schedule does not move.
  const double at = on_schedule ? (patient_ ? last_ + period_ : scheduled) : now;
  patient_ = woken_ && at - last_ < 1.2 * period_;
  // The token is spent when the run really happened: an early tick counted in its slot must
  // not keep an input that comes before that slot waiting for it.
  tokens_ = std::max(-1.0, tokensAt(now) - 1.0);
  ran_at_ = now;
  last_ = at;
  woken_ = false;
}

}  // namespace robot_core
