// The Autopilot: drives a differential-drive base to an absolute pose (x, y, heading) in the
// map, the `goto` action's controller. Pure computation, one step per control period, so it
// is tested on a kinematic model without ROS.
//
// Phases: TURN (face the target in place while the bearing error is large), DRIVE (speed from
// the speed curve on the remaining distance, heading corrected by the turn curve, speed reduced
// as the bearing error grows), ROTATE (on the target, turn to the final heading), SETTLE
// (command zero until the limiter has stopped). Close to the target (near_radius) it stops
// steering toward the point and only closes the distance along its heading: chasing a point a
// few millimetres away sideways is what makes robots circle around their goal.
#pragma once

#include <string>

#include "hal_nodes/driver/control_curves.h"
#include "hal_nodes/driver/geometry.h"
#include "hal_nodes/driver/motion_limits.h"

namespace hal_nodes {
namespace driver {

struct AutopilotConfig {
  ControlCurve speed_curve{0.3, 0.7};  // distance [m] -> fraction of the speed limit
  ControlCurve turn_curve{0.6, 0.8};   // angular deviation [rad] -> fraction of the turn limit
  MotionLimits limits;
  double turn_in_place_angle = 0.6;    // [rad] bearing error above which the robot turns without driving
  double near_radius = 0.04;           // [m] within it, close the distance along the heading only

  std::string invalidReason() const;   // empty when usable
};

struct AutopilotGoal {
  Pose2D target;
  double position_tolerance = 0.01;  // [m]
  double angle_tolerance = 0.035;    // [rad]; >= pi: any final heading
  double max_speed = 0.0;            // [m/s]; 0: the configured limit
  bool allow_reverse = false;        // drive backwards when the target is behind
  bool final_heading = true;         // false: a waypoint, done on arrival at the point (no stop/rotate)
};

class Autopilot {
 public:
  enum class Phase { TURN, DRIVE, ROTATE, SETTLE, DONE };

  explicit Autopilot(const AutopilotConfig& config) : config_(config) {}

  void start(const AutopilotGoal& goal, const Pose2D& from);

  // The command for this period, before the limiter (the caller limits it, so the curves can
  // ask for anything). `current` is the last limited command; `measured` (odometry's twist,
  // optional) is what the wheels really do: SETTLE ends only when both are still, and a robot
  // that rolled out of tolerance while stopping is brought back instead of reported done.
  Twist2D step(const Pose2D& pose, const Twist2D& current, const Twist2D* measured = nullptr);

  Phase phase() const { return phase_; }
  bool done() const { return phase_ == Phase::DONE; }
  double remainingDistance() const { return remaining_; }
  double headingError() const { return heading_error_; }
  // 0..100: distance covered since start() over the distance to cover (heading for a pure rotation).
  double progressPercent() const { return progress_; }
  const AutopilotGoal& goal() const { return goal_; }
  static const char* phaseName(Phase p);

 private:
  Twist2D turnTo(double error, double max_speed) const;

  AutopilotConfig config_;
  AutopilotGoal goal_;
  Phase phase_ = Phase::DONE;
  double start_distance_ = 0.0;
  double start_angle_ = 0.0;
  double remaining_ = 0.0;
  double heading_error_ = 0.0;
  double progress_ = 0.0;
  int direction_ = 1;  // +1 forward, -1 backwards for this goal
};

}  // namespace driver
}  // namespace hal_nodes
