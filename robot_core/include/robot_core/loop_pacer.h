// When a periodic loop that an input may wake runs next (the HAL's device loops, the HCL's
// board loops). The pull model's loops poll at their configured rate; an input that matters at
// once (a ranger reading, a motor command) wakes its loop instead of waiting up to a period for
// the next tick. A configured ceiling (max_rate, by default the rate itself) bounds the runs:
//   * runs are paced by a token bucket at the ceiling holding at most two tokens: over any
//     window of T seconds the loop runs at most T * max_rate + 2 times, so a flood of inputs
//     cannot raise it. One spare token lets an input that comes between two ticks be served at
//     once, and the loop's phase then follows its inputs;
//   * a loop woken by a stream as fast as its ceiling has no margin: every extra run (a tick
//     while an input was late, a second source) costs a token for good, and from then on each
//     input waits for its token, a fixed part of a period, for the rest of the run. A ceiling
//     above the stream's rate refills what such runs take;
//   * without inputs the loop runs once per period, drift-free, like a plain timer;
//   * after a woken run that came within 1.2 periods of the run before it (inputs at the loop's
//     own rate), the next tick waits half a period longer: an input that comes a little late
//     then still finds the loop ready instead of a tick that has just taken its place. The
//     schedule itself does not move, so slower inputs never pull the loop below its rate.
// Time is passed in (seconds of ROS time), so it is testable and follows the simulated clock.
#pragma once

namespace robot_core {

class LoopPacer {
 public:
  static constexpr double kBurst = 2.0;  // tokens the bucket holds

  // `period_s`: the loop's period without inputs; `min_interval_s` (<= period_s, 0: the period):
  // 1 / the ceiling, the token bucket's refill.
  explicit LoopPacer(double period_s, double min_interval_s = 0.0)
      : period_(period_s), min_interval_(min_interval_s > 0.0 && min_interval_s < period_s ? min_interval_s : period_s) {}

  // An input arrived: the loop runs at next(), at once when it has a token.
  void wake() { woken_ = true; }
  bool woken() const { return woken_; }

  // When the loop runs next; -infinity before its first run (run at once).
  double next() const;
  bool due(double now) const { return now >= next(); }
  // For a periodic timer's tick: the timer and the pacer keep the same period but their
  // callback latencies differ, so a tick up to half a period before next() is on time (else
  // one tick in two would be skipped whenever a tick came a little early).
  // (The patience after a woken run is kept whole.)
  bool dueForTick(double now) const {
    return woken_ || patient_ ? due(now) : now >= next() - 0.5 * period_;
  }

  // The loop ran at `now`.
  void ran(double now);

  double period() const { return period_; }

 private:
  static constexpr double kPatience = 0.5;  // [periods] the next tick's wait after a woken run at the loop's rate
  double period_;
  double min_interval_;
  bool started_ = false;
  bool woken_ = false;
  bool patient_ = false;  // the last run was woken within 1.2 periods of the one before
  double last_ = 0.0;    // when the last run counts as having happened (its schedule, if on time)
  double ran_at_ = 0.0;  // when it really happened
  double tokens_ = 0.0;  // tokens left just after it
  double tokensAt(double t) const;
};

}  // namespace robot_core
