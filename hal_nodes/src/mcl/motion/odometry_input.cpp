#include "hal_nodes/mcl/motion/odometry_input.h"

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

void OdometryInput::addPose(std::size_t pair, const Pose2& odom_pose) {
  State& s = pairs_.at(pair);
  if (!s.has_ref) {
    s.ref = odom_pose;
    s.has_ref = true;
    return;
  }
  addIncrement(pair, between(s.ref, odom_pose));
  s.ref = odom_pose;
}

void OdometryInput::addIncrement(std::size_t pair, const Pose2& delta) {
  State& s = pairs_.at(pair);
  s.delta = s.moved ? compose(s.delta, delta) : delta;
  s.moved = true;
}

Pose2 OdometryInput::pending() const {
  // Reliability-weighted average of the pairs that moved (headings are small increments).
  double wsum = 0.0;
  Pose2 d{0, 0, 0};
  for (const auto& s : pairs_) {
    if (!s.moved) continue;
    wsum += s.cfg.reliability;
    d.x += s.cfg.reliability * s.delta.x;
    d.y += s.cfg.reliability * s.delta.y;
    d.theta += s.cfg.reliability * s.delta.theta;
  }
  if (wsum <= 0.0) return {0, 0, 0};
  return {d.x / wsum, d.y / wsum, d.theta / wsum};
}

void OdometryInput::advance(ParticleSet& set, const StepContext& ctx) {
  bool any = false;
  for (const auto& s : pairs_) any |= s.moved;
  if (!any) return;
  const Pose2 d = pending();
  for (auto& s : pairs_) {
    s.moved = false;
    s.delta = {0, 0, 0};
  }
  model_.apply(set, d, *ctx.rng);
}

}  // namespace hal_nodes::mcl
