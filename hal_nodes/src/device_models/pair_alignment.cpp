#include "hal_nodes/devices/odometry/pair_alignment.h"

#include <algorithm>

namespace hal_nodes {

namespace {

// The count at `instant`, linear between an earlier sample and a later one.
double countAt(const CounterSample& before, const CounterSample& after, double instant) {
  if (after.stamp <= instant) return after.ticks;
  if (before.stamp >= instant) return before.ticks;
  return before.ticks + (after.ticks - before.ticks) * (instant - before.stamp) / (after.stamp - before.stamp);
}

}  // namespace

bool PairAlignment::finishStart(const CounterSample& left, const CounterSample& right) {
  if (!starting_) {
    starting_ = true;
    common_stamp_ = std::max(left.stamp, right.stamp);
  } else if (left.stamp >= common_stamp_ && right.stamp >= common_stamp_) {
    left_ticks_ = countAt(left_before_, left, common_stamp_);
    right_ticks_ = countAt(right_before_, right, common_stamp_);
    starting_ = false;
    started_ = true;
    return true;
  }
  if (left.stamp <= common_stamp_) left_before_ = left;
  if (right.stamp <= common_stamp_) right_before_ = right;
  return false;
}

std::optional<AlignedStep> PairAlignment::advance(const CounterSample& left, const CounterSample& right) {
  if (!started_ && !finishStart(left, right)) return std::nullopt;
  const double instant = std::min(left.stamp, right.stamp);
  if (instant <= common_stamp_) return std::nullopt;
  const double l = countAt({common_stamp_, left_ticks_}, left, instant);
  const double r = countAt({common_stamp_, right_ticks_}, right, instant);
  AlignedStep step;
  step.stamp = instant;
  step.dt = instant - common_stamp_;
  step.left_ticks = l - left_ticks_;
  step.right_ticks = r - right_ticks_;
  common_stamp_ = instant;
  left_ticks_ = l;
  right_ticks_ = r;
  return step;
}

}  // namespace hal_nodes
