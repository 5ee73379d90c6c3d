// Odometry as an advancing input: one or more encoder pairs (a drive pair, an idle measuring
// pair, ...). Each pair reports its own pose in its odom frame; the increments since the last
// step are combined as a weighted average by each pair's configured reliability (pairs that
// reported nothing new do not vote), and the motion model adds per-particle noise.
//
// Slip detection (motion model's slip_accel > 0, increments with stamps): a pair that travelled
// further than the robot can have gone since its last increment has a wheel spinning (the
// encoders jump; a robot's speed cannot). Its increment is cut to the travel at the pair's
// last speed, it does not vote while another pair moved without slipping, and if every pair
// slipped the step carries the slip's heading noise on every particle. Only too much travel
// is a slip: a sudden stop (a collision) is what the robot did. Stamps may jitter by up to a
// period (taken on reception): see detectSlip().
#pragma once

#include <limits>
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
  // `stamp` [s] is the pose's time (NaN: unknown, no slip detection for this increment).
  void addPose(std::size_t pair, const Pose2D& odom_pose, double stamp = kNoStamp);
  // Feed a pair's increment directly (robot frame), e.g. from a recorded run.
  void addIncrement(std::size_t pair, const Pose2D& delta, double stamp = kNoStamp);
  // The combined increment waiting to be applied (zero if none).
  Pose2D pending() const;
  void advance(ParticleSet& set, const StepContext& ctx) override;
  double travelled() const override { return travelled_; }
  const MotionModel& model() const { return model_; }
  // Increments found slipping so far, all pairs.
  std::size_t slips() const { return slips_; }

  static constexpr double kNoStamp = std::numeric_limits<double>::quiet_NaN();

 private:
  struct State {
    Pair cfg;
    bool has_ref = false;
    Pose2D ref;
    Pose2D delta;   // accumulated since the last advance, robot frame at the last advance
    bool moved = false;
    bool slipped = false;  // some increment since the last advance was cut as a slip
    double stamp = kNoStamp;
    double speed = kNoStamp;         // forward speed of the last increment [m/s]
    double speed_before = kNoStamp;  // and of the one before
    double period = kNoStamp;        // usual time between increments (running mean) [s]
  };
  // Cut an increment the robot cannot have made to its last speed (see above).
  void detectSlip(State& s, Pose2D& delta, double stamp);
  std::vector<State> pairs_;
  MotionModel model_;
  std::size_t slips_ = 0;
  double travelled_ = 0.0;  // [m] sum of the applied increments' translations
};

}  // namespace hal_nodes::mcl
