// Odometry as an advancing input: one or more encoder pairs (a drive pair, an idle measuring
// pair, ...). Each pair reports its own pose in its odom frame; the increments since the last
// step are combined as a weighted average by each pair's configured reliability (pairs that
// reported nothing new do not vote), and the motion model adds per-particle noise.
#pragma once

#include <string>
#include <vector>

#include "hal_nodes/mcl/input.h"
#include "hal_nodes/mcl/motion/motion_model.h"

namespace hal_nodes::mcl {

class OdometryInput : public AdvancingInput {
 public:
  struct Pair {
    std::string name;
    double reliability = 1.0;
  };

  OdometryInput(const std::vector<Pair>& pairs, const MotionModel& model);

  std::size_t pairIndex(const std::string& name) const;  // throws std::out_of_range
  std::size_t pairCount() const { return pairs_.size(); }
  // Feed a pair's newest pose (its own odom frame); the first call only sets the reference.
  void addPose(std::size_t pair, const Pose2& odom_pose);
  // Feed a pair's increment directly (robot frame), e.g. from a recorded run.
  void addIncrement(std::size_t pair, const Pose2& delta);
  // The combined increment waiting to be applied (zero if none).
  Pose2 pending() const;
  void advance(ParticleSet& set, const StepContext& ctx) override;
  const MotionModel& model() const { return model_; }

 private:
  struct State {
    Pair cfg;
    bool has_ref = false;
    Pose2 ref;
    Pose2 delta;   // accumulated since the last advance, robot frame at the last advance
    bool moved = false;
  };
  std::vector<State> pairs_;
  MotionModel model_;
};

}  // namespace hal_nodes::mcl
