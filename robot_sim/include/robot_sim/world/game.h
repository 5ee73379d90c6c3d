// The game on the table: its elements (where they lie, who carries them, who moved them last),
// our robot's collectors and grippers, the pushing of elements by both robots, and the referee
// (the match's start and end, the colours, the points per team and the scoring events).
// Not thread-safe: SimWorld locks around it.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "robot_sim/world/actuators.h"
#include "robot_sim/world/config.h"
#include "robot_sim/world/footprint.h"
#include "robot_sim/world/robot_body.h"

namespace robot_sim {

// The referee's account: points per team, frozen at the end of the match.
struct MatchProgress {
  bool started = false;
  bool over = false;
  double elapsed = 0.0;    // since the start [s]
  double remaining = 0.0;  // [s]
  int score_ours = 0;
  int score_opponent = 0;
  std::string colour_ours, colour_opponent;  // start zones at the start ("" before it)
};

// An element came to lie in a scoring zone (points > 0) or left it (points < 0) during the match.
struct RefereeEvent {
  double time = 0.0;    // match time [s]
  std::string element;  // kind#index in the config's element list
  std::string zone;
  int points = 0;
  Mover team = Mover::nobody;  // whose points
};

class Game {
 public:
  explicit Game(const WorldConfig& config);

  // One step of the elements: our collectors and grippers (their motor commands and finger
  // servos), the elements each robot carries riding along, loose ones pushed out of our outline
  // and of the opponent's circle (when there is one).
  void stepElements(double dt, const RobotBody& ours, const std::map<std::string, ServoState>& servos,
                    const std::optional<Circle>& opponent);

  // ---- the referee ----
  // The match starts: our colour is the start zone our robot stands in, the opponent's the one
  // it stands in, else another start zone.
  void begin(double time, const Pose2D& ours, const std::optional<Pose2D>& opponent);
  // Each step: where every element scores now, the events, and the end of the match.
  void referee(double time);
  bool started() const { return started_; }
  bool over() const { return over_; }
  MatchProgress progress(double time) const;
  const std::vector<RefereeEvent>& events() const { return events_; }
  // Which team a zone's points go to for this element: a team colour's, or the last mover's.
  Mover zoneTeam(const Zone& zone, const GameElement& e) const;
  const std::string& colourOurs() const { return colour_ours_; }
  const std::string& colourOpponent() const { return colour_opponent_; }

  // ---- the elements, for the opponent that plays ----
  const std::vector<GameElement>& elements() const { return elements_; }
  // The opponent takes element `i` (false when it is carried already), or puts it down at (x, y).
  bool takeByOpponent(std::size_t i);
  void putDownByOpponent(std::size_t i, double x, double y);
  const TableConfig& table() const { return table_; }

 private:
  struct Collector {
    CollectorConfig config;
    int held = 0;
    double eject_cooldown = 0.0;
    std::vector<std::size_t> gripped;  // a gripper's elements (indices into elements_)
    std::vector<std::pair<std::size_t, double>> entering;  // a collector's, at its mouth: [s] left of the intake
    bool was_closed = false;           // a gripper grips once per closing
  };
  void stepGripper(Collector& c, const RobotBody& ours, const std::map<std::string, ServoState>& servos);
  void stepCollector(Collector& c, double dt, const RobotBody& ours);
  bool kindOk(const std::vector<std::string>& kinds, const GameElement& e) const;
  bool isGripped(const GameElement& e) const;

  TableConfig table_;
  MatchConfig match_;
  bool opponent_enabled_;
  std::vector<GameElement> elements_;
  std::map<std::string, Collector> collectors_;
  bool started_ = false;
  bool over_ = false;
  double start_time_ = 0.0;
  // Where each element scores now (index into score_zones, -1: nowhere) and for whom.
  struct Scoring {
    int zone = -1;
    Mover team = Mover::nobody;
  };
  std::vector<Scoring> scoring_;
  std::vector<RefereeEvent> events_;
  std::string colour_ours_, colour_opponent_;
};

}  // namespace robot_sim
