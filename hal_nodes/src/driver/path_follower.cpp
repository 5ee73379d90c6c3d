#include "hal_nodes/driver/path_follower.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hal_nodes {
namespace driver {

std::string PathFollowerConfig::invalidReason() const {
  if (!(convergence_distance >= 0.02 && convergence_distance <= 1.0)) return "convergence_distance must be in [0.02, 1]";
  if (!(sample_step > 0.0 && sample_step <= 0.1)) return "sample_step must be in (0, 0.1]";
  if (!(max_lateral_accel > 0.0)) return "max_lateral_accel must be > 0";
  if (!(lookahead_time >= 0.0 && lookahead_time <= 0.5)) return "lookahead_time must be in [0, 0.5]";
  if (!(heading_correction_speed >= 0.0 && heading_correction_speed <= 1.0)) return "heading_correction_speed must be in [0, 1]";
  return "";
}

void PathFollower::start(std::vector<PathSample> samples, double tolerance, double max_speed) {
  samples_ = std::move(samples);
  index_ = 0;
  tolerance_ = tolerance;
  const double lim = base_.limits.max_linear_speed;
  max_speed_ = max_speed > 0.0 ? std::min(max_speed, lim) : lim;
  remaining_ = samples_.empty() ? 0.0 : samples_.back().s;
  cross_track_ = 0.0;
  settling_ = false;
  finishing_ = false;
  done_ = samples_.empty();
}

int PathFollower::segment() const {
  if (samples_.empty()) return 0;
  if (done_) return samples_.back().segment + 1;
  // The last sample of a segment is its checkpoint: passed when the robot is at or past it.
  const std::size_t i = index_;
  if (i + 1 < samples_.size() && samples_[i + 1].segment != samples_[i].segment) return samples_[i].segment + 1;
  return samples_[i].segment;
}

double PathFollower::progressPercent() const {
  if (done_) return 100.0;
  const double total = samples_.empty() ? 0.0 : samples_.back().s;
  return total > 0.0 ? 100.0 * std::clamp(1.0 - remaining_ / total, 0.0, 1.0) : 100.0;
}

Twist2D PathFollower::step(const Pose2D& pose, const Twist2D& current) {
  if (done_ || samples_.empty()) return Twist2D();
  if (finishing_) {
    const Twist2D cmd = finish_.step(pose, current);
    remaining_ = finish_.remainingDistance();
    done_ = finish_.done();
    return cmd;
  }
  const MotionLimits& lim = base_.limits;

  // Progress: the closest sample within a window ahead (never backwards: the curve may cross itself).
  const double D = config_.convergence_distance;
  const double window = std::max(0.3, 3.0 * D);
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_i = index_;
  for (std::size_t i = index_; i < samples_.size() && samples_[i].s <= samples_[index_].s + window; ++i) {
    const double dd = std::hypot(samples_[i].x - pose.x, samples_[i].y - pose.y);
    if (dd < best) {
      best = dd;
      best_i = i;
    }
  }
  index_ = best_i;
  cross_track_ = best;

  const PathSample& ref = samples_[index_];
  const PathSample& end = samples_.back();
  const double c = std::cos(pose.theta), s = std::sin(pose.theta);
  const double to_end_x = end.x - pose.x, to_end_y = end.y - pose.y;
  const double d_end = std::hypot(to_end_x, to_end_y);
  const double along_end = to_end_x * std::cos(end.heading) + to_end_y * std::sin(end.heading);  // along the final tangent
  const double arc_left = end.s - ref.s;
  const bool final_approach = index_ + 1 == samples_.size();
  remaining_ = final_approach ? std::max(0.0, along_end) : arc_left + std::max(0.0, (ref.x - pose.x) * c + (ref.y - pose.y) * s);

  // Only on the last segment: a curve that comes back to where it starts is not done at its start.
  const bool last_segment = ref.segment == end.segment;
  if (!settling_ && last_segment && (d_end <= 0.5 * tolerance_ || (d_end <= tolerance_ && along_end <= 0.0))) settling_ = true;
  if (settling_ && d_end > 2.0 * tolerance_) settling_ = false;
  if (settling_) {
    if (current.v == 0.0 && current.w == 0.0) done_ = true;
    return Twist2D();
  }
  if (final_approach && along_end <= 0.5 * tolerance_ && d_end > tolerance_) {  // at the end, but beside it
    AutopilotGoal goal;
    goal.target = {end.x, end.y, end.heading};
    goal.position_tolerance = tolerance_;
    goal.max_speed = max_speed_;
    goal.allow_reverse = true;
    finish_.start(goal, pose);
    finishing_ = true;
    return step(pose, current);
  }

  // Errors in the curve's frame at the reference point (left of the robot / turned left: positive).
  const double e_y = -(pose.x - ref.x) * std::sin(ref.heading) + (pose.y - ref.y) * std::cos(ref.heading);
  const double lateral = -e_y;  // the curve is to the left when the robot is to its right
  const double e_theta = wrapAngle(ref.heading - pose.theta);
  const double ang_decel = 0.9 * lim.max_angular_accel;
  if (std::fabs(e_theta) > base_.turn_in_place_angle) {  // facing away from the curve: turn onto it first
    const double w = std::min(lim.max_angular_speed * std::fabs(base_.turn_curve.fraction(e_theta)),
                              brakingSpeed(std::fabs(e_theta), ang_decel));
    return Twist2D{0.0, sign(e_theta) * w};
  }
  const double dist = final_approach ? std::fabs(along_end) : remaining_;
  const double decel = 0.9 * lim.max_linear_accel;
  double speed = std::min(max_speed_ * base_.speed_curve.fraction(dist), brakingSpeed(dist, decel));
  speed *= std::max(0.0, 1.0 - std::fabs(e_theta) / base_.turn_in_place_angle);
  // Bends ahead: slow enough now to be at each bend's speed when it comes.
  const double horizon = max_speed_ * max_speed_ / (2.0 * decel) + D;
  for (std::size_t k = index_; k < samples_.size() && samples_[k].s - ref.s <= horizon; ++k) {
    // Curvature needs turn rate (v * kappa), its change along the curve turn acceleration (v^2 * dkappa/ds).
    const double kappa = std::fabs(samples_[k].curvature);
    double bend = kappa > 1e-6 ? std::min(std::sqrt(config_.max_lateral_accel / kappa), 0.8 * lim.max_angular_speed / kappa)
                               : max_speed_;
    if (k + 1 < samples_.size() && samples_[k + 1].s > samples_[k].s) {
      const double dkds = std::fabs(samples_[k + 1].curvature - samples_[k].curvature) / (samples_[k + 1].s - samples_[k].s);
      if (dkds > 1e-6) bend = std::min(bend, std::sqrt(0.5 * lim.max_angular_accel / dkds));
    }
    speed = std::min(speed, std::sqrt(bend * bend + 2.0 * decel * (samples_[k].s - ref.s)));
  }
  double kappa = 0.0;
  if (!final_approach) {  // the bend the robot will be in once this command takes effect
    std::size_t k = index_;
    const double s_ahead = ref.s + speed * config_.lookahead_time;
    while (k + 1 < samples_.size() && samples_[k].s < s_ahead) ++k;
    kappa = samples_[k].curvature;
  }
  const double offset = std::clamp(lateral, -D, D);
  // The lateral term needs motion to act; the heading term does not (the robot can turn on the spot).
  const double heading_speed = std::max(speed, config_.heading_correction_speed);
  return Twist2D{speed, speed * (kappa + offset / (D * D)) + 2.0 * heading_speed / D * e_theta};
}

}  // namespace driver
}  // namespace hal_nodes
