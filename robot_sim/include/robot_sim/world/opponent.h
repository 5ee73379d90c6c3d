// The opponent robot: a circle that drives like a robot (turn on the spot, then go, slowing on
// arrival) towards the targets of its mode:
//   static       stays where it is;
//   script       its waypoints in a loop, pausing at each (make matches' route and blocker);
//   random_walk  random points at least `margin` from the borders, pausing at each;
//   player       plays the game for the other colour (robot_sim/world/opponent_player.h).
// Like a robot with its own sensors it keeps `safety_distance` from our outline: it never drives
// closer (it may always drive away). Blocked by us for `give_way_after`, it backs off up to
// `back_off` where its rear is free, then a random walker takes a target away from us, a script
// its next waypoint, a player another task. Nothing moves before the match starts.
#pragma once

#include <memory>
#include <vector>

#include "robot_sim/world/config.h"
#include "robot_sim/world/footprint.h"
#include "robot_sim/world/random.h"
#include "robot_sim/world/table_geometry.h"

namespace robot_sim {

class Game;
class OpponentPlayer;

class Opponent {
 public:
  Opponent(const OpponentConfig& config, const TableGeometry& table);
  ~Opponent();

  // One step. `ours`: our robot's outline; `game`: the elements and the referee (a player takes
  // and puts down elements, everyone waits for the start).
  void step(double dt, const PlacedFootprint& ours, Rng& rng, Game& game);

  const Pose2D& pose() const { return pose_; }
  double v() const { return v_; }
  double w() const { return w_; }
  double radius() const { return config_.radius; }
  Circle outline() const { return Circle{pose_.x, pose_.y, config_.radius}; }
  const OpponentConfig& config() const { return config_; }

  // Puts the opponent at `pose`; `hold` keeps it there until released (hold = false).
  void place(const Pose2D& pose, bool hold);
  bool holding() const { return hold_; }

 private:
  enum class Move { arrived, moving, blocked_by_us, blocked_by_border };
  // Turns towards target_ and drives to it: one step of motion, never into our safety distance.
  Move driveTowards(double dt, const PlacedFootprint& ours);
  void backOff(double dt, const PlacedFootprint& ours);
  void nextTarget(Rng& rng, const PlacedFootprint& ours, Game& game, bool away_from_us);
  // Whether a step from pose_ to `next` is allowed: not deeper into the borders, not closer to
  // us than the safety distance (unless it gets further away).
  bool intoBorder(const Pose2D& next) const;
  bool intoUs(const Pose2D& next, const PlacedFootprint& ours) const;

  OpponentConfig config_;
  TableGeometry table_;
  Pose2D pose_;
  double v_ = 0.0, w_ = 0.0;
  Point2D target_;
  std::size_t waypoint_ = 0;
  double pause_left_ = 0.0;
  double blocked_for_ = 0.0;   // [s] blocked by us (or by a border) on the way to target_
  double backing_left_ = 0.0;  // [m] still to back off
  double clock_ = 0.0;         // [s] its own time since the start of the run
  bool hold_ = false;
  bool has_target_ = false;
  std::unique_ptr<OpponentPlayer> player_;
};

}  // namespace robot_sim
