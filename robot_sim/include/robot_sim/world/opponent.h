// The opponent robot: a circle that drives (turn, then go) to waypoints from a script or to
// random points (random walk), pausing at each; it waits while our robot is in the way.
#pragma once

#include <vector>

#include "robot_sim/world/config.h"
#include "robot_sim/world/footprint.h"
#include "robot_sim/world/random.h"
#include "robot_sim/world/table_geometry.h"

namespace robot_sim {

class Opponent {
 public:
  Opponent(const OpponentConfig& config, const TableGeometry& table);

  // One step; `ours` is our robot's outline in map (the opponent never drives into it).
  void step(double dt, const std::vector<Point2D>& ours, Rng& rng);

  const Pose2D& pose() const { return pose_; }
  double v() const { return v_; }
  double w() const { return w_; }
  double radius() const { return config_.radius; }
  Circle outline() const { return Circle{pose_.x, pose_.y, config_.radius}; }

  // Puts the opponent at `pose`; `hold` keeps it there until released (hold = false).
  void place(const Pose2D& pose, bool hold);
  bool holding() const { return hold_; }

 private:
  void nextTarget(Rng& rng);

  OpponentConfig config_;
  TableGeometry table_;
  Pose2D pose_;
  double v_ = 0.0, w_ = 0.0;
  Point2D target_;
  std::size_t waypoint_ = 0;
  double pause_left_ = 0.0;
  double blocked_for_ = 0.0;
  bool hold_ = false;
  bool has_target_ = false;
};

}  // namespace robot_sim
