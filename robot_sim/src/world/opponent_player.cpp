#include "robot_sim/world/opponent_player.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "robot_sim/world/game.h"

namespace robot_sim {

namespace {
constexpr double kSetAside = 10.0;     // [s] a task our robot blocked waits this long
constexpr double kGap = 0.01;          // [m] between the opponent's front and an element it goes for
constexpr double kReach = 0.05;        // [m] an element this far past the front is still within reach
constexpr double kSpotStep = 0.06;     // [m] grid of the spots tried in a zone
constexpr double kRetargetMoved = 0.02;  // [m] an element pushed this far is driven to again

double dist(double ax, double ay, double bx, double by) { return std::hypot(ax - bx, ay - by); }
}  // namespace

OpponentPlayer::OpponentPlayer(const OpponentConfig& config) : config_(config) {}

bool OpponentPlayer::isOwn(const std::string& kind) const {
  return std::find(own_kinds_.begin(), own_kinds_.end(), kind) != own_kinds_.end();
}

// Its own elements: the kinds a zone of its colour counts (a zone of its colour with no kinds
// counts every kind that any zone names).
void OpponentPlayer::learnTheRules(const Game& game) {
  rules_known_ = true;
  const std::string& colour = game.colourOpponent();
  for (const Zone& z : game.table().score_zones) {
    if (z.team != colour) continue;
    for (const std::string& k : z.kinds)
      if (!isOwn(k)) own_kinds_.push_back(k);
  }
}

bool OpponentPlayer::liesScoring(const Game& game, std::size_t i) const {
  const GameElement& e = game.elements()[i];
  for (const Zone& z : game.table().score_zones)
    if ((z.kinds.empty() || std::count(z.kinds.begin(), z.kinds.end(), e.kind)) && z.contains(e.pose.x, e.pose.y))
      return true;
  return false;
}

int OpponentPlayer::bestZone(const Game& game, const std::string& kind, const Pose2D& me) const {
  const auto& zones = game.table().score_zones;
  int best = -1;
  for (std::size_t z = 0; z < zones.size(); ++z) {
    const Zone& zone = zones[z];
    const bool counts = zone.kinds.empty() || std::count(zone.kinds.begin(), zone.kinds.end(), kind);
    const bool ours_to_score = zone.team == game.colourOpponent() || zone.team.empty() || zone.team == "placer";
    if (!counts || !ours_to_score || zone.points <= 0) continue;
    if (best < 0 || zone.points > zones[best].points) {
      best = static_cast<int>(z);
    } else if (zone.points == zones[best].points) {
      const Zone& b = zones[best];
      if (dist(me.x, me.y, 0.5 * (zone.x0 + zone.x1), 0.5 * (zone.y0 + zone.y1)) <
          dist(me.x, me.y, 0.5 * (b.x0 + b.x1), 0.5 * (b.y0 + b.y1)))
        best = static_cast<int>(z);
    }
  }
  return best;
}

// Where the opponent's centre stands to have `at` just ahead of its front, coming from `me`.
Point2D OpponentPlayer::standOff(const Pose2D& me, const Point2D& at, double element_radius) const {
  const double d = dist(at.x, at.y, me.x, me.y);
  const double ux = d > 1e-9 ? (at.x - me.x) / d : 1.0, uy = d > 1e-9 ? (at.y - me.y) / d : 0.0;
  const double back = config_.radius + element_radius + kGap;
  return Point2D{at.x - ux * back, at.y - uy * back};
}

// A free spot in the zone (no loose element within two radii) whose stand-off keeps the
// opponent on the table, the nearest to it first.
std::optional<Point2D> OpponentPlayer::putDownSpot(const Game& game, int zone, const Pose2D& me,
                                                   double element_radius) const {
  const Zone& z = game.table().score_zones[zone];
  const double m = element_radius + 0.005;
  std::vector<Point2D> spots;
  for (double x = z.x0 + m; x <= z.x1 - m + 1e-9; x += kSpotStep)
    for (double y = z.y0 + m; y <= z.y1 - m + 1e-9; y += kSpotStep) spots.push_back({x, y});
  std::sort(spots.begin(), spots.end(), [&](const Point2D& a, const Point2D& b) {
    return dist(a.x, a.y, me.x, me.y) < dist(b.x, b.y, me.x, me.y);
  });
  const double length = game.table().length, width = game.table().width;
  for (const Point2D& p : spots) {
    bool free = true;
    for (const GameElement& e : game.elements())
      if (!e.carried && dist(e.pose.x, e.pose.y, p.x, p.y) < element_radius + e.radius + 0.01) free = false;
    const Point2D c = standOff(me, p, element_radius);
    const double r = config_.radius + 0.005;
    if (free && c.x >= r && c.x <= length - r && c.y >= r && c.y <= width - r) return p;
  }
  return std::nullopt;
}

std::optional<Point2D> OpponentPlayer::nextTarget(const Pose2D& me, const PlacedFootprint& ours, const Game& game,
                                                  double now) {
  if (!game.started() || game.over()) return std::nullopt;
  if (!rules_known_) learnTheRules(game);
  task_ = Task::none;
  const auto& elements = game.elements();
  // Something to take on the way, while there is room, before putting down what it holds.
  if (static_cast<int>(held_.size()) < config_.player_capacity) {
    double best_cost = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < elements.size(); ++i) {
      const GameElement& e = elements[i];
      if (e.carried || !isOwn(e.kind) || liesScoring(game, i)) continue;
      auto aside = set_aside_until_.find(i);
      if (aside != set_aside_until_.end() && now < aside->second) continue;
      // Near our robot: contested, left alone (it would have to come within its safety distance).
      const double near_us = ours.shape->boundingRadius() + config_.safety_distance + e.radius + 0.05;
      if (dist(e.pose.x, e.pose.y, ours.pose.x, ours.pose.y) < near_us) continue;
      const int zone = bestZone(game, e.kind, me);
      if (zone < 0) continue;
      const Zone& z = game.table().score_zones[zone];
      const double cost = dist(e.pose.x, e.pose.y, me.x, me.y) +
                          dist(e.pose.x, e.pose.y, 0.5 * (z.x0 + z.x1), 0.5 * (z.y0 + z.y1));
      if (cost < best_cost) {
        best_cost = cost;
        element_ = i;
      }
    }
    if (std::isfinite(best_cost)) {
      task_ = Task::take;
      element_at_ = {elements[element_].pose.x, elements[element_].pose.y};
      return standOff(me, element_at_, elements[element_].radius);
    }
  }
  if (held_.empty() || now < zone_set_aside_until_) return std::nullopt;
  const GameElement& first = elements[held_.front()];
  const int zone = bestZone(game, first.kind, me);
  if (zone < 0) return std::nullopt;
  const auto spot = putDownSpot(game, zone, me, first.radius);
  if (!spot) return std::nullopt;
  task_ = Task::put_down;
  spot_ = *spot;
  return standOff(me, spot_, first.radius);
}

std::optional<Point2D> OpponentPlayer::retarget(const Pose2D& me, const Game& game) {
  if (task_ != Task::take) return std::nullopt;
  const GameElement& e = game.elements()[element_];
  if (e.carried) {
    task_ = Task::none;  // our robot took it
    return std::nullopt;
  }
  if (dist(e.pose.x, e.pose.y, element_at_.x, element_at_.y) < kRetargetMoved) return std::nullopt;
  element_at_ = {e.pose.x, e.pose.y};
  return standOff(me, element_at_, e.radius);
}

double OpponentPlayer::arrived(const Pose2D& me, Game& game) {
  const Task task = task_;
  task_ = Task::none;
  if (task == Task::take) {
    const GameElement& e = game.elements()[element_];
    const double reach = config_.radius + e.radius + kGap + kReach;
    if (!e.carried && dist(e.pose.x, e.pose.y, me.x, me.y) <= reach && game.takeByOpponent(element_)) {
      held_.push_back(element_);
      return config_.player_handling_time;
    }
    return 0.0;  // it moved away: choose again
  }
  if (task == Task::put_down) {
    // Side by side across the direction it faces, when it holds several.
    const double c = std::cos(me.theta), s = std::sin(me.theta);
    for (std::size_t k = 0; k < held_.size(); ++k) {
      const GameElement& e = game.elements()[held_[k]];
      const double side = (static_cast<double>(k) - 0.5 * static_cast<double>(held_.size() - 1)) * 2.2 * e.radius;
      game.putDownByOpponent(held_[k], spot_.x - s * side, spot_.y + c * side);
    }
    held_.clear();
    return config_.player_handling_time;
  }
  return 0.0;
}

void OpponentPlayer::giveUp(double now) {
  if (task_ == Task::take) set_aside_until_[element_] = now + kSetAside;
  if (task_ == Task::put_down) zone_set_aside_until_ = now + 0.5 * kSetAside;
  task_ = Task::none;
}

}  // namespace robot_sim
