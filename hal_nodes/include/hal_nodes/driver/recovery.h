// Recoveries: what the driver tries, in its configured order, before a goal ends BLOCKED (a
// stall, or a route blocked past avoidance/blocked_timeout), as move_base's recovery_behaviors
// and Nav2's BackUp, Spin and Wait do:
//   back_off        drive backwards `distance` [m], only where the rear is free: the rear rangers
//                   see nothing within distance + rear_margin (a robot that cannot see behind
//                   does not back off blind); it stops short when something comes within rear_margin
//   turn_other_way  a turn that stalled goes the other way round to the same heading
//   wait            stand still `duration` [s] (an opponent moves away)
// Each runs once per goal, in the order given, on odometry alone; after one the goal goes on from
// where the robot is. A recovery that does not apply (rear not free, not turning) is skipped.
// The goal ends BLOCKED when the list is used up; an empty list ends it at once.
// Pure computation (one step per control period), tested without ROS.
#pragma once

#include <robot_core/params.h>

#include <string>
#include <vector>

#include "hal_nodes/driver/autopilot.h"
#include "hal_nodes/driver/relative_moves.h"

namespace hal_nodes {
namespace driver {

struct RecoveryStep {
  enum class Kind { BACK_OFF, TURN_OTHER_WAY, WAIT };
  Kind kind = Kind::WAIT;
  double distance = 0.12;  // [m] back_off
  double duration = 1.0;   // [s] wait
  double max_speed = 0.0;  // [m/s or rad/s] back_off, turn_other_way; 0: the configured limit
  static const char* name(Kind kind);
};

struct RecoveryConfig {
  std::vector<RecoveryStep> steps;
  std::vector<std::string> rear_rangers;  // names on avoidance/ranger_prefix looking backwards
  double rear_margin = 0.05;              // [m] kept free behind a back-off
};

// recovery/{behaviors: [{type: back_off|turn_other_way|wait, distance, duration, max_speed}],
// rear_rangers, rear_margin}; no block: no recovery (today's behaviour).
RecoveryConfig readRecoveryConfig(const robot_core::Params& driver);

// What the driver knows when a goal is blocked.
struct BlockedAt {
  Pose2D odom;               // the robot in the odom frame
  double turn_left = 0.0;    // [rad] signed turn still to make when it stalled; 0: it was not turning
  double rear_free = -1.0;   // [m] free behind (the rear rangers' nearest echo); < 0: unknown
};

class Recovery {
 public:
  Recovery(const RecoveryConfig& config, const AutopilotConfig& motion);

  // A new goal: the whole list again.
  void reset();
  // Starts the next recovery that applies; false when the list is used up. `skipped` gets what
  // did not apply and why ("back_off: rear not free (0.08 m)").
  bool start(const BlockedAt& at, double now, std::vector<std::string>* skipped);
  bool running() const { return running_; }
  // One control period while it runs: the command; running() turns false when it is over.
  // `rear_free`: as in BlockedAt, for a back-off to stop short.
  Twist2D step(const Pose2D& odom, const Twist2D& current, double now, double rear_free);

  // "back_off (1 of 3)" while one runs, "" otherwise.
  std::string describe() const;
  // The recoveries tried on this goal, in order ("back_off, wait").
  std::string tried() const;
  std::size_t count() const { return config_.steps.size(); }
  const RecoveryConfig& config() const { return config_; }

 private:
  RecoveryConfig config_;
  StraightMove straight_;
  Rotation rotation_;
  std::size_t next_ = 0;     // the next step to try
  std::size_t current_ = 0;  // the step running
  bool running_ = false;
  double until_ = 0.0;       // wait: its end
  std::vector<std::string> tried_;
};

}  // namespace driver
}  // namespace hal_nodes
