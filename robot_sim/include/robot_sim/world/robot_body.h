// Our robot's body on the table: its motors, the wheels' slip, the encoders, its pose, and its
// contacts with the borders and the opponent (only the part of a step that goes into an obstacle
// is cancelled: robot_sim/world/contact_solver.h), which close the bumper at the contact.
// Not thread-safe: SimWorld locks around it.
#pragma once

#include <map>
#include <string>

#include "robot_sim/world/config.h"
#include "robot_sim/world/contact_solver.h"
#include "robot_sim/world/footprint.h"
#include "robot_sim/world/motor_model.h"
#include "robot_sim/world/random.h"

namespace robot_sim {

class RobotBody {
 public:
  // Throws ConfigError when the robot has no left or no right drive motor.
  RobotBody(const RobotConfig& config, unsigned seed);

  // One step: motors, wheel slip, the motion with its contacts, encoders, bumpers.
  void step(double dt, const Obstacles& obstacles);

  const Footprint& footprint() const { return footprint_; }
  const Pose2D& pose() const { return pose_; }
  PlacedFootprint placed() const { return PlacedFootprint{&footprint_, pose_}; }
  double v() const { return v_; }  // forward speed over the last step [m/s]
  double w() const { return w_; }  // yaw rate [rad/s]
  Pose2D toMap(double x, double y) const;  // a base_link point on the table

  // Motors by name; false for a name the robot does not have.
  bool hasMotor(const std::string& name) const { return motors_.count(name) > 0; }
  bool setMotorCommand(const std::string& name, double fraction);
  const MotorState* motor(const std::string& name) const;
  // A drive motor's extra slip fraction (the wheel_slip fault); false when `name` is no drive motor.
  bool setExtraSlip(const std::string& name, double fraction);

  bool hasEncoder(const std::string& name) const { return encoders_.count(name) > 0; }
  int64_t encoderTicks(const std::string& name) const;  // 0 for an unknown name

  // A bumper closes when the outline touches an obstacle within its angular span.
  bool bumperClosed(const SwitchConfig& bumper) const;
  bool inContact() const { return contact_; }

  // Puts the robot at `pose`, at rest.
  void teleport(const Pose2D& pose);

 private:
  struct Motor {
    MotorConfig config;
    MotorState state;
    double extra_slip = 0.0;
    double ground_speed = 0.0;  // wheel contact speed [m/s]
  };
  struct Encoder {
    EncoderConfig config;
    double turns = 0.0;  // wheel revolutions
  };

  RobotConfig config_;
  Footprint footprint_;
  Pose2D pose_;
  double v_ = 0.0, w_ = 0.0;
  std::map<std::string, Motor> motors_;
  Motor* left_ = nullptr;
  Motor* right_ = nullptr;
  std::map<std::string, Encoder> encoders_;
  Rng slip_rng_;
  bool contact_ = false;
  double contact_angle_ = 0.0;  // base_link: direction of the contact point on the outline
};

}  // namespace robot_sim
