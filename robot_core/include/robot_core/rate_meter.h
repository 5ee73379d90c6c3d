// Measures how well a polling loop keeps its rate: a moving-average loops-per-second over a
// sliding window, the period jitter (the "time resolution" of the original Scheduler) and
// how long each service() call took. Time is passed in, so it is testable and works
// under simulated time.
#pragma once

#include <cstddef>
#include <deque>

namespace robot_core {

class RateMeter {
 public:
  explicit RateMeter(double window_s = 1.0);

  // A loop iteration started at time t [s] and its work took `busy_s` seconds.
  void tick(double t, double busy_s = 0.0);

  double rate() const;            // loops per second over the window; 0 with fewer than 2 ticks
  double maxPeriodError(double expected_period) const;  // worst |period - expected| in the window [s]
  double meanBusy() const;        // mean duration of the work in the window [s]
  double maxBusy() const;         // longest work in the window [s]
  std::size_t count() const { return ticks_.size(); }

 private:
  struct Tick {
    double t;
    double busy;
  };
  void trim(double now);
  double window_;
  std::deque<Tick> ticks_;
};

}  // namespace robot_core
