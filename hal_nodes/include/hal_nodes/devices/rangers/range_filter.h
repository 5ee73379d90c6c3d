// The rangers' filter (SRF02 ultrasound, SHARP infrared): raw readings in, a trustworthy
// range out. Three stages, in this order:
//  1. Nonsense: NaN, negative, below the sensor's minimum range (inside its blind zone the
//     firmware reports garbage) are dropped and counted; they never reach the output.
//     +inf or a reading at/above the maximum range means "no echo": it is kept, as +inf
//     (REP-117), because "nothing there" is information too.
//  2. Peaks: a reading within `step` of the previous one, or of the line through the previous
//     two (a range sweeping along a wall while the robot turns), continues them and passes
//     unchanged and undelayed. Any other reading is a jump: the median of the last `window`
//     readings replaces it, so a lone spike (a cross-talk echo, one missed echo) is outvoted
//     and a real jump passes once the next reading continues it (or after window/2 + 1).
//     With `nearer_at_once`, a jump to a nearer range passes at once: for the rangers that
//     guard against collisions a false stop costs less than a stop one reading late (20 ms,
//     4 cm at full speed). Use it where nearer spikes are rare (infrared, not ultrasound
//     cross-talk).
//  3. Noise: an exponential moving average of stage 2 with weight `smoothing` for the
//     newest value. It restarts at that value when it moves by more than `step` (a new
//     obstacle must not be delayed by the smoothing) or to/from "no echo".
#pragma once

#include <cstddef>
#include <deque>
#include <optional>

namespace hal_nodes {

struct RangeFilterConfig {
  std::size_t window = 5;  // odd, >= 1
  double smoothing = 0.5;  // 0 < smoothing <= 1; 1 = no smoothing
  double step = 0.10;      // [m]
  bool nearer_at_once = false;
};

class RangeFilter {
 public:
  enum class Verdict { kAccepted, kNoEcho, kNonsense };

  explicit RangeFilter(RangeFilterConfig config = RangeFilterConfig()) : config_(config) {}

  // Add one raw reading with the sensor's limits; returns the filtered range (+inf: nothing
  // seen) or nothing while the reading was nonsense and there is no output yet.
  std::optional<double> add(double range, double min_range, double max_range, Verdict* verdict = nullptr);

  std::optional<double> value() const { return output_; }
  void reset();
  unsigned long nonsense() const { return nonsense_; }

 private:
  RangeFilterConfig config_;
  std::deque<double> window_;
  std::optional<double> output_;
  unsigned long nonsense_ = 0;
};

}  // namespace hal_nodes
