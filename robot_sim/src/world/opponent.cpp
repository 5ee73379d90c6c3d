#include "robot_sim/world/opponent.h"

#include <algorithm>
#include <cmath>

#include "robot_sim/world/diff_drive.h"
#include "robot_sim/world/game.h"
#include "robot_sim/world/opponent_player.h"

namespace robot_sim {

namespace {
constexpr double kArrived = 0.01;        // [m] at the target
constexpr int kAwayTries = 20;           // random targets tried for one away from us
}  // namespace

Opponent::Opponent(const OpponentConfig& config, const TableGeometry& table)
    : config_(config), table_(table), pose_(config.start) {
  if (config_.mode == "player") player_ = std::make_unique<OpponentPlayer>(config_);
}

Opponent::~Opponent() = default;

void Opponent::place(const Pose2D& pose, bool hold) {
  pose_ = pose;
  hold_ = hold;
  has_target_ = false;
  backing_left_ = 0.0;
  blocked_for_ = 0.0;
  v_ = w_ = 0.0;
}

void Opponent::nextTarget(Rng& rng, const PlacedFootprint& ours, Game& game, bool away_from_us) {
  has_target_ = false;
  blocked_for_ = 0.0;
  if (player_) {
    if (auto t = player_->nextTarget(pose_, ours, game, clock_)) {
      target_ = *t;
      has_target_ = true;
    }
    return;
  }
  if (config_.mode == "script") {
    target_ = config_.waypoints[waypoint_];
    waypoint_ = (waypoint_ + 1) % config_.waypoints.size();
    has_target_ = true;
    return;
  }
  // Random walk: a uniform point; away from us, the first one on our far side.
  const double m = std::min(config_.margin, 0.5 * std::min(table_.length(), table_.width()));
  for (int i = 0; i < (away_from_us ? kAwayTries : 1); ++i) {
    target_ = {rng.uniform(m, table_.length() - m), rng.uniform(m, table_.width() - m)};
    const double ax = target_.x - pose_.x, ay = target_.y - pose_.y;
    const double ux = ours.pose.x - pose_.x, uy = ours.pose.y - pose_.y;
    if (ax * ux + ay * uy < 0.0) break;
  }
  has_target_ = true;
}

bool Opponent::intoBorder(const Pose2D& next) const {
  const double now = borderClearance(table_, pose_.x, pose_.y, config_.radius);
  const double then = borderClearance(table_, next.x, next.y, config_.radius);
  return then < 0.0 && then < now;
}

bool Opponent::intoUs(const Pose2D& next, const PlacedFootprint& ours) const {
  const double now = ours.circleContact(Circle{pose_.x, pose_.y, config_.radius}).clearance;
  const double then = ours.circleContact(Circle{next.x, next.y, config_.radius}).clearance;
  return then < config_.safety_distance && then < now;
}

Opponent::Move Opponent::driveTowards(double dt, const PlacedFootprint& ours) {
  const double dx = target_.x - pose_.x, dy = target_.y - pose_.y;
  const double dist = std::hypot(dx, dy);
  if (dist < kArrived) return Move::arrived;
  const double err = wrapAngle(std::atan2(dy, dx) - pose_.theta);
  w_ = std::clamp(err / dt, -config_.turn_rate, config_.turn_rate);
  // Turn on the spot first, then drive (slowing down on arrival).
  if (std::abs(err) < 0.2) v_ = std::min(config_.speed, dist / dt);
  Pose2D next = integrateTwist(pose_, v_, w_, dt);
  Move result = Move::moving;
  if (intoUs(next, ours) || intoBorder(next)) {
    result = intoUs(next, ours) ? Move::blocked_by_us : Move::blocked_by_border;
    v_ = 0.0;  // turning on the spot is always free: a circle
    next = integrateTwist(pose_, 0.0, w_, dt);
  }
  pose_ = next;
  return result;
}

void Opponent::backOff(double dt, const PlacedFootprint& ours) {
  const double v = -config_.speed;
  const Pose2D next = integrateTwist(pose_, v, 0.0, dt);
  if (intoUs(next, ours) || intoBorder(next)) {
    backing_left_ = 0.0;  // the rear is not free: as far as it goes
    return;
  }
  v_ = v;
  pose_ = next;
  backing_left_ -= std::abs(v) * dt;
}

void Opponent::step(double dt, const PlacedFootprint& ours, Rng& rng, Game& game) {
  v_ = w_ = 0.0;
  clock_ += dt;
  if (hold_ || config_.mode == "static") return;
  if (!game.started() || game.over()) return;  // a robot waits for the start, and stops at the end
  if (backing_left_ > 0.0) {
    backOff(dt, ours);
    if (backing_left_ <= 0.0) {
      // Another target: a player's other task, a script's next waypoint, a random one away from us.
      if (player_) player_->giveUp(clock_);
      nextTarget(rng, ours, game, config_.mode == "random_walk");
    }
    return;
  }
  if (pause_left_ > 0.0) {
    pause_left_ -= dt;
    return;
  }
  if (!has_target_) {
    nextTarget(rng, ours, game, false);
    if (!has_target_) return;  // a player with nothing left to do
  }
  if (player_) {
    if (auto t = player_->retarget(pose_, game)) target_ = *t;
  }
  switch (driveTowards(dt, ours)) {
    case Move::arrived:
      has_target_ = false;
      pause_left_ = player_ ? player_->arrived(pose_, game) : config_.pause;
      return;
    case Move::moving:
      blocked_for_ = 0.0;
      return;
    case Move::blocked_by_us:
      blocked_for_ += dt;
      if (blocked_for_ >= config_.give_way_after) {
        blocked_for_ = 0.0;
        backing_left_ = config_.back_off;
        if (backing_left_ <= 0.0) backing_left_ = 1e-9;  // no back-off: straight to another target
      }
      return;
    case Move::blocked_by_border:
      // A target it cannot reach along the border: a random walker takes another one.
      blocked_for_ += dt;
      if (blocked_for_ > config_.give_way_after && config_.mode != "script") nextTarget(rng, ours, game, false);
      return;
  }
}

}  // namespace robot_sim
