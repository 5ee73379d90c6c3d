// Brings the two counters of an encoder pair to one instant before they are compared.
//
// The two counters arrive on separate topics (often from separate boards), so at any refresh
// one side may be a sample newer than the other. Integrating them as they are reads the newer
// side's extra travel as a turn; the heading comes back once the other side catches up, but
// the sideways drift made meanwhile never does. Instead each step ends at the newest instant
// both sides have reached (the older of the two stamps): the side sampled later is
// interpolated linearly at that instant between its count there and the last common instant,
// and the rest of its travel is counted in the next step. The start is aligned the same way:
// it is the newer of the first two stamps, and the side sampled earlier is interpolated there
// once it has a sample at or past it.
#pragma once

#include <optional>

namespace hal_nodes {

// One counter reading: cumulative (unwrapped) ticks and the time of the board exchange.
struct CounterSample {
  double stamp = 0.0;  // [s]
  double ticks = 0.0;
};

// The travel of both sides between two common instants.
struct AlignedStep {
  double stamp = 0.0;  // [s] the new common instant
  double dt = 0.0;     // [s] since the previous one
  double left_ticks = 0.0;
  double right_ticks = 0.0;
};

class PairAlignment {
 public:
  // The next call to advance only sets the common instant (first use, back from stale).
  void restart() { started_ = starting_ = false; }
  bool started() const { return started_; }

  // The step from the last common instant to the newest one both samples reach; nothing when
  // neither side has moved past the last one yet (or this call only set the start).
  std::optional<AlignedStep> advance(const CounterSample& left, const CounterSample& right);

 private:
  // Both samples reach the start instant: the common counts there.
  bool finishStart(const CounterSample& left, const CounterSample& right);

  bool started_ = false;
  bool starting_ = false;                 // the start instant is chosen, a side has not reached it
  CounterSample left_before_, right_before_;  // while starting: each side's newest sample so far
  double common_stamp_ = 0.0;
  double left_ticks_ = 0.0, right_ticks_ = 0.0;  // counts at common_stamp_
};

}  // namespace hal_nodes
