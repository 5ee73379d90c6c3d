// The simulated world as the firmware emulators see it: the contract between the world
// (robot_sim/world, issue "robot_sim") and every board emulator (CAN, I2C, serial, joystick,
// camera). Emulators find their motors, encoders and sensors by the names given in
// config/<robot>.yaml (sim/world/robot/...), so one emulator serves any robot.
//
// Thread safety: every method may be called from any emulator thread while the world steps.
// Units: SI, REP-103 (x forward, y left, z up, angles counter-clockwise) in the `map` frame
// (origin at a table corner, x along the 3 m side).
#pragma once

#include <robot_core/geometry.h>

#include <cstdint>
#include <string>
#include <vector>

namespace robot_sim {

using robot_core::Pose2D;

// One beacon receiver measurement: the receiver reports a time difference per beacon.
struct BeaconMeasurement {
  int beacon_id = 0;    // 0, 1, 2
  double stamp = 0.0;   // simulated time of the transmit slot [s]
  double delta_s = 0.0; // time of flight of the ultrasonic pulse [s] (noise, outliers applied)
};

// Who last moved a game element (pushed it, or carried it and let it go): the referee credits
// an element lying in a shared zone to that robot.
enum class Mover { nobody, ours, opponent };

struct GameElement {
  std::string kind;     // "ball_red", "ball_white", "column", ...
  Pose2D pose;
  double radius = 0.0;  // [m]
  double height = 0.0;  // [m]
  bool carried = false; // held by a robot: `carrier`
  Mover carrier = Mover::nobody;
  Mover moved_by = Mover::nobody;
};

// Everything a camera renderer or a test needs in one consistent copy.
struct WorldSnapshot {
  double time = 0.0;
  Pose2D robot;
  double robot_radius = 0.0;
  Pose2D opponent;
  double opponent_radius = 0.0;
  std::vector<GameElement> elements;
  double table_length = 3.0;  // x extent [m]
  double table_width = 2.1;   // y extent [m]
};

class World {
 public:
  virtual ~World() = default;

  // Simulated time [s] since the start of the run.
  virtual double time() const = 0;

  // ---- actuators ----
  // Motor drive command as a fraction of full voltage, -1..1 (clamped). The motor follows
  // with its configured lag, acceleration and current limits.
  virtual void setMotorCommand(const std::string& motor, double fraction) = 0;
  virtual double motorCurrent(const std::string& motor) const = 0;          // [A]
  virtual void setServoTarget(const std::string& servo, double position) = 0;   // [rad]
  virtual double servoPosition(const std::string& servo) const = 0;             // [rad]
  virtual void setStepperTarget(const std::string& stepper, int64_t steps) = 0;
  virtual int64_t stepperPosition(const std::string& stepper) const = 0;

  // ---- sensors (noise, bias and faults already applied) ----
  // Unbounded tick count of an encoder; the firmware wraps it to its own counter width.
  virtual int64_t encoderTicks(const std::string& encoder) const = 0;
  // Range [m] seen by a ranger (SRF02, SHARP); +inf or the sensor's max when nothing is seen.
  virtual double measureRange(const std::string& ranger) = 0;
  // Compass heading [deg] clockwise from the table's magnetic north, 0..360.
  virtual double measureCompassDeg() = 0;
  virtual bool switchClosed(const std::string& name) const = 0;  // bumpers, end and limit switches
  virtual double batteryVoltage() const = 0;                     // [V]
  // Beacon measurements produced since the last call (consumed by the receiver emulator).
  virtual std::vector<BeaconMeasurement> takeBeaconMeasurements() = 0;

  virtual WorldSnapshot snapshot() const = 0;

  // ---- added (not pure, so existing fakes keep compiling) ----
  // Whether the robot has a device of this kind ("motor", "encoder", "ranger", "switch",
  // "servo", "stepper") and name. Emulators check their configured names at start; a read of
  // an unknown name returns 0 / false / +inf and is counted, never throws.
  virtual bool has(const std::string& kind, const std::string& name) const {
    (void)kind;
    (void)name;
    return true;
  }
};

}  // namespace robot_sim
