// The simulated world, advanced by step(): the table with our robot's body (robot_body.h: motors,
// encoders, motion and contacts), its servos, steppers, switches and sensors, the game (game.h:
// elements, collectors, the referee), the opponent (opponent.h) and the world-side faults
// (world_faults.h). Implements the World contract for the firmware emulators plus the
// simulator's controls (teleport, opponent placement, switches, faults) and ground truth.
//
// Thread safety: every public method locks one mutex; step() runs in the simulator's thread.
// Determinism: step() draws only from dynamics streams, sensor reads from per-sensor streams,
// so the trajectory depends on the seed and the timed commands only.
#pragma once

#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include <robot_core/priority_inheritance_mutex.h>

#include "robot_sim/world/actuators.h"
#include "robot_sim/world/beacon_model.h"
#include "robot_sim/world/config.h"
#include "robot_sim/world/footprint.h"
#include "robot_sim/world/game.h"
#include "robot_sim/world/opponent.h"
#include "robot_sim/world/random.h"
#include "robot_sim/world/robot_body.h"
#include "robot_sim/world/table_geometry.h"
#include "robot_sim/world/world.h"

namespace robot_sim {

struct BodyTruth {
  Pose2D pose;
  double v = 0.0;  // forward speed [m/s]
  double w = 0.0;  // yaw rate [rad/s]
};

class SimWorld : public World {
 public:
  SimWorld(const WorldConfig& config, unsigned seed);

  // ---- World ----
  double time() const override;
  void setMotorCommand(const std::string& motor, double fraction) override;
  double motorCurrent(const std::string& motor) const override;
  void setServoTarget(const std::string& servo, double position) override;
  double servoPosition(const std::string& servo) const override;
  void setStepperTarget(const std::string& stepper, int64_t steps) override;
  int64_t stepperPosition(const std::string& stepper) const override;
  int64_t encoderTicks(const std::string& encoder) const override;
  double measureRange(const std::string& ranger) override;
  double measureCompassDeg() override;
  bool switchClosed(const std::string& name) const override;
  double batteryVoltage() const override;
  std::vector<BeaconMeasurement> takeBeaconMeasurements() override;
  WorldSnapshot snapshot() const override;
  bool has(const std::string& kind, const std::string& name) const override;

  // ---- the simulator's side ----
  void step();                  // advances one dt
  double dt() const { return config_.dt; }
  const WorldConfig& config() const { return config_; }
  const Footprint& footprint() const { return robot_.footprint(); }  // our outline in base_link

  // Motor commands applied exactly at simulated time `at` (a scripted, reproducible drive).
  void scheduleMotorCommand(double at, const std::string& motor, double fraction);

  void teleport(const Pose2D& pose);
  void placeOpponent(const Pose2D& pose, bool hold);
  bool setSwitch(const std::string& name, bool closed);  // manual switches only

  // World-side faults: "beacon_silent" (target: beacon id "0".."2"), "wheel_slip" (target: a
  // drive motor, magnitude: extra slip fraction, default 0.6), "opponent_blocks" (the opponent
  // steps in front of our robot and stays, magnitude: gap [m], default 0.1). False + why for others.
  bool applyFault(const std::string& kind, const std::string& target, bool active, double magnitude,
                  std::string* why);
  static bool isWorldFault(const std::string& kind);

  BodyTruth robotTruth() const;
  BodyTruth opponentTruth() const;
  MatchProgress match() const;
  std::vector<RefereeEvent> scoreEvents() const;  // every event since the start, in order
  std::size_t scoreEventCount() const;
  // Starts the match as the start cord does (the cord switch opens); false if it had started.
  bool startMatch();
  std::vector<GameElement> elements() const;
  double trueRange(const std::string& ranger) const;  // noiseless, for tests
  // Names asked for that this robot does not have ("motor 'lft'"): a config mismatch between
  // an emulator block and sim/world/robot, reported by the simulator. An empty name means
  // "not connected": it reads 0 / false / +inf and is not counted.
  int unknownNameCount() const;
  std::vector<std::string> unknownNames() const;

 private:
  void stepMatch();
  Obstacles obstacles() const;  // what our robot's motion meets: borders, the opponent
  std::vector<Circle> rangerObstacles(bool with_elements) const;
  void applyScheduled();
  template <class M>
  typename M::mapped_type* find(M& m, const std::string& name, const char* kind) const;
  void noteUnknown(const char* kind, const std::string& name) const;

  const WorldConfig config_;
  const unsigned seed_;
  // Read by the boards' emulators in real-time threads while the stepping thread updates it:
  // the stepping thread gets their priority while it holds the world.
  using Mutex = robot_core::PriorityInheritanceMutex;
  mutable Mutex mutex_;
  TableGeometry table_;
  double time_ = 0.0;
  long steps_ = 0;
  RobotBody robot_;
  Game game_;
  std::map<std::string, ServoState> servos_;
  std::map<std::string, StepperState> steppers_;
  std::map<std::string, bool> manual_switches_;
  std::deque<std::pair<double, std::pair<std::string, double>>> scheduled_;
  Opponent opponent_;
  BeaconModel beacons_;
  // Random streams: dynamics (used by step only) and one per sensor.
  Rng opponent_rng_, beacon_rng_;
  std::map<std::string, Rng> ranger_rng_;
  Rng compass_rng_;
  mutable Rng battery_rng_;
  mutable int unknown_names_ = 0;
  mutable std::set<std::string> unknown_list_;
};

}  // namespace robot_sim
