#include "hal_nodes/mcl/motion/odometry_input.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hal_nodes::mcl {

OdometryInput::OdometryInput(const std::vector<Pair>& pairs, const MotionModel& model)
    : AdvancingInput("odometry"), model_(model) {
  if (pairs.empty()) throw std::invalid_argument("odometry: at least one encoder pair is needed");
  model_.validate();
  for (const auto& p : pairs) {
    if (!(p.reliability > 0.0 && p.reliability <= 1.0))
      throw std::invalid_argument("odometry pair " + p.name + ": reliability must be in (0, 1]");
    State s;
    s.cfg = p;
    pairs_.push_back(s);
  }
}

std::size_t OdometryInput::pairIndex(const std::string& name) const {
  for (std::size_t i = 0; i < pairs_.size(); ++i)
    if (pairs_[i].cfg.name == name) return i;
  throw std::out_of_range("odometry: no encoder pair named '" + name + "'");
}

void OdometryInput::addPose(std::size_t pair, const Pose2D& odom_pose, double stamp) {
  State& s = pairs_.at(pair);
  if (!s.has_ref) {
    s.ref = odom_pose;
    s.has_ref = true;
    s.stamp = stamp;
    return;
  }
  addIncrement(pair, between(s.ref, odom_pose), stamp);
  s.ref = odom_pose;
}

void OdometryInput::addIncrement(std::size_t pair, const Pose2D& delta, double stamp) {
  State& s = pairs_.at(pair);
  Pose2D d = delta;
  detectSlip(s, d, stamp);
  s.delta = s.moved ? compose(s.delta, d) : d;
  s.moved = true;
}

void OdometryInput::detectSlip(State& s, Pose2D& delta, double stamp) {
  double dt = stamp - s.stamp;  // NaN when either is unknown
  if (!std::isnan(stamp)) s.stamp = stamp;
  if (!(model_.slip_accel > 0.0) || !(dt > 0.0)) return;
  // Stamps taken on reception jitter: a message that came late is followed by one that comes
  // early with a full period's travel. Judge each increment over at least the usual period.
  s.period = std::isnan(s.period) ? dt : s.period + 0.1 * (dt - s.period);
  dt = std::max(dt, s.period);
  const double travel = std::fabs(delta.x);
  if (!std::isnan(s.speed)) {
    // The faster of the last two speeds: one increment that came late (its travel over a
    // longer time) does not make the next one look too fast.
    const double speed = std::isnan(s.speed_before) ? std::fabs(s.speed)
                                                    : std::max(std::fabs(s.speed), std::fabs(s.speed_before));
    const double possible = (speed + model_.slip_accel * dt) * dt + model_.slip_margin;
    if (travel > possible) {
      // The wheel turned further than the robot can have gone: the robot most likely went on
      // at its speed (lateral part in proportion); the heading is left to the slip's noise.
      const double keep = speed * dt / travel, direction = delta.x;
      delta.x *= keep;
      delta.y *= keep;
      // The next increment is judged against what the robot can have reached by now, so a
      // robot really driven (or pushed) faster is followed again after a few increments.
      s.speed_before = s.speed;
      s.speed = std::copysign(speed + model_.slip_accel * dt, direction);
      s.slipped = true;
      ++slips_;
      return;
    }
  }
  s.speed_before = s.speed;
  s.speed = delta.x / dt;
}

Pose2D OdometryInput::pending() const {
  // Reliability-weighted average of the pairs that moved (headings are small increments); a
  // slipping pair is outvoted by any pair that moved without slipping.
  bool any_sound = false;
  for (const auto& s : pairs_) any_sound |= s.moved && !s.slipped;
  double wsum = 0.0;
  Pose2D d{0, 0, 0};
  for (const auto& s : pairs_) {
    if (!s.moved || (any_sound && s.slipped)) continue;
    wsum += s.cfg.reliability;
    d.x += s.cfg.reliability * s.delta.x;
    d.y += s.cfg.reliability * s.delta.y;
    d.theta += s.cfg.reliability * s.delta.theta;
  }
  if (wsum <= 0.0) return {0, 0, 0};
  return {d.x / wsum, d.y / wsum, d.theta / wsum};
}

void OdometryInput::advance(ParticleSet& set, const StepContext& ctx) {
  bool any = false, all_slipped = true;
  for (const auto& s : pairs_) {
    any |= s.moved;
    if (s.moved) all_slipped &= s.slipped;
  }
  if (!any) return;
  const Pose2D d = pending();
  for (auto& s : pairs_) {
    s.moved = false;
    s.slipped = false;
    s.delta = {0, 0, 0};
  }
  travelled_ += std::hypot(d.x, d.y);
  model_.apply(set, d, *ctx.rng, all_slipped);
}

}  // namespace hal_nodes::mcl
