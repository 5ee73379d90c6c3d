#include "robot_sim/world/opponent.h"

#include <algorithm>
#include <cmath>

#include "robot_sim/world/diff_drive.h"

namespace robot_sim {

Opponent::Opponent(const OpponentConfig& config, const TableGeometry& table)
    : config_(config), table_(table), pose_(config.start) {}

void Opponent::place(const Pose2D& pose, bool hold) {
  pose_ = pose;
  hold_ = hold;
  has_target_ = false;
  v_ = w_ = 0.0;
}

void Opponent::nextTarget(Rng& rng) {
  if (config_.mode == "script") {
    target_ = config_.waypoints[waypoint_];
    waypoint_ = (waypoint_ + 1) % config_.waypoints.size();
  } else {
    const double m = std::min(config_.margin, 0.5 * std::min(table_.length(), table_.width()));
    target_ = {rng.uniform(m, table_.length() - m), rng.uniform(m, table_.width() - m)};
  }
  has_target_ = true;
  blocked_for_ = 0.0;
}

void Opponent::step(double dt, const std::vector<Point2D>& ours, Rng& rng) {
  v_ = w_ = 0.0;
  if (hold_ || config_.mode == "static") return;
  if (pause_left_ > 0.0) {
    pause_left_ -= dt;
    return;
  }
  if (!has_target_) nextTarget(rng);
  const double dx = target_.x - pose_.x, dy = target_.y - pose_.y;
  const double dist = std::hypot(dx, dy);
  if (dist < 0.01) {
    has_target_ = false;
    pause_left_ = config_.pause;
    return;
  }
  const double err = wrapAngle(std::atan2(dy, dx) - pose_.theta);
  w_ = std::clamp(err / dt, -config_.turn_rate, config_.turn_rate);
  // Turn on the spot first, then drive (slowing down on arrival).
  if (std::abs(err) < 0.2) v_ = std::min(config_.speed, dist / dt);
  Pose2D next = integrateTwist(pose_, v_, w_, dt);
  const Circle me{next.x, next.y, config_.radius};
  const Circle now{pose_.x, pose_.y, config_.radius};
  const double gap_next = circleContact(ours, me).clearance;
  const bool into_us = gap_next < 0.0 && gap_next < circleContact(ours, now).clearance;
  const bool into_border = borderClearance(table_, next.x, next.y, config_.radius) < 0.0 &&
                           borderClearance(table_, next.x, next.y, config_.radius) <
                               borderClearance(table_, pose_.x, pose_.y, config_.radius);
  if (into_us || into_border) {
    // Wait for us to move; a random walker gives up on this target after a while.
    v_ = 0.0;
    next = integrateTwist(pose_, 0.0, w_, dt);
    blocked_for_ += dt;
    if (blocked_for_ > 2.0 && config_.mode == "random_walk") has_target_ = false;
  }
  pose_ = next;
}

}  // namespace robot_sim
