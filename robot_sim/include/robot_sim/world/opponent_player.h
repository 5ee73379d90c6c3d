// The opponent that plays the game for the other colour: it takes its own elements (the kinds a
// zone of its colour counts), at most `capacity` at a time, carries them to the zone that gives
// it the most points for them (its own zones, or one open to both teams such as the 2009
// temple), and puts them down there. It leaves alone what already scores and what lies near our
// robot, and sets a task aside for a while when our robot blocks it.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "robot_sim/world/config.h"
#include "robot_sim/world/footprint.h"

namespace robot_sim {

class Game;

class OpponentPlayer {
 public:
  explicit OpponentPlayer(const OpponentConfig& config);

  // Where to drive next from `me`; nothing when there is nothing left to do.
  std::optional<Point2D> nextTarget(const Pose2D& me, const PlacedFootprint& ours, const Game& game, double now);
  // Each step on the way: the target again when the element it drives to has moved.
  std::optional<Point2D> retarget(const Pose2D& me, const Game& game);
  // Arrived at the target: takes the element or puts down what it holds. Returns the handling time [s].
  double arrived(const Pose2D& me, Game& game);
  // Our robot blocked the way: the task is set aside for a while.
  void giveUp(double now);
  int held() const { return static_cast<int>(held_.size()); }

 private:
  enum class Task { none, take, put_down };
  void learnTheRules(const Game& game);
  bool isOwn(const std::string& kind) const;
  bool liesScoring(const Game& game, std::size_t i) const;
  // The zone that scores the most for `kind` (nearest of equals); -1: none.
  int bestZone(const Game& game, const std::string& kind, const Pose2D& me) const;
  std::optional<Point2D> putDownSpot(const Game& game, int zone, const Pose2D& me, double element_radius) const;
  Point2D standOff(const Pose2D& me, const Point2D& at, double element_radius) const;

  OpponentConfig config_;
  bool rules_known_ = false;
  std::vector<std::string> own_kinds_;
  std::vector<std::size_t> held_;
  Task task_ = Task::none;
  std::size_t element_ = 0;  // take: which
  Point2D element_at_;       // take: where it was when planned
  Point2D spot_;             // put_down: where the elements go
  std::map<std::size_t, double> set_aside_until_;  // element -> time
  double zone_set_aside_until_ = -1.0;
};

}  // namespace robot_sim
