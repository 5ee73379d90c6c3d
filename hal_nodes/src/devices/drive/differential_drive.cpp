// DifferentialDrive: the motor interface every robot's motor boards implement. Takes
// geometry_msgs/Twist on ~cmd_vel (/hal/drive/cmd_vel) and sends each wheel motor an
// hcl_drivers/MotorCommand in its board's native unit (PWM duty, speed register, EPOS rpm:
// ~wheels/<name>/units_per_mps from config). A command older than ~cmd_timeout stops the
// wheels; deactivation commands zero at once and ignores cmd_vel until reactivated.
// Commands are sent at ~rate even when they do not change, so the boards' own command
// timeouts never stop a robot that is being driven, and do stop one whose HAL died.
// Teleop: a top-level /cmd_vel (teleop_twist_keyboard, joy's teleop_twist_joy, rqt) drives the
// base too, at a lower priority: only while ~cmd_vel (the brain, the driver) has been quiet for
// ~cmd_timeout, each teleop command for ~teleop_timeout (diff_drive_controller's
// cmd_vel_timeout), and never during a match: from the start (the latched /effectors/match_end
// the brain publishes) until its end. A stranger's cmd_vel must not steer a robot in a match.
//
// ~wheel_speed_clamp is the effector's last guard: the driver plans within its own
// limits/max_wheel_speed.
// Parameters: read and described in configure() (the table: hal_nodes/PARAMETERS.md, make docs).
#include <geometry_msgs/Twist.h>
#include <hcl_drivers/MotorCommand.h>
#include <std_msgs/Time.h>

#include <atomic>
#include <cmath>
#include <mutex>

#include "hal_nodes/device_nodelet.h"
#include <robot_core/params.h>
#include "hal_nodes/devices/drive/wheel_speeds.h"

namespace hal_nodes {

class DifferentialDrive : public Effector {
 public:
  void configure(const robot_core::Params& params) override {
    track_width_ = robot_core::RobotGeometry::blockOrDescribed(params, "track_width", robot().track_width, "track_width",
                                                               "[m] the distance between the driven wheels");
    const std::string clamp = params.renamed("wheel_speed_clamp", "max_wheel_speed");
    params.describe(clamp, "[m/s] faster wheel speeds are scaled down keeping the curvature");
    wheel_speed_clamp_ = params.requireDouble(clamp);
    params.requirePositive(clamp, wheel_speed_clamp_);
    params.describe("max_acceleration", "[m/s^2] the acceleration limit of each wheel (0: none)");
    max_acceleration_ = params.optionalDouble("max_acceleration", 0.0);
    params.requireInRange("max_acceleration", max_acceleration_, 0.0, 1e3);
    params.describe("cmd_timeout", "[s] a cmd_vel older than this stops the wheels (and lets teleop drive)");
    cmd_timeout_ = params.optionalDouble("cmd_timeout", 0.3);
    params.requirePositive("cmd_timeout", cmd_timeout_);
    bool has_left = false, has_right = false;
    motors_.clear();
    params.describe("wheels", "the wheel motors, by name; at least one on each side");
    for (const auto& name : params.requireBlockNames("wheels")) {
      const robot_core::Params p = params.block("wheels/" + name);
      Motor m;
      p.describe("side", "the wheel's side");
      const std::string side = p.requireString("side");
      p.requireOneOf("side", side, {"left", "right"});
      m.left = side == "left";
      (m.left ? has_left : has_right) = true;
      p.describe("motor", "the MotorCommand's name (absent: the block's name)");
      m.motor = p.optionalString("motor", name);
      p.describe("units_per_mps", "native units per m/s of wheel surface speed, non-zero (negative: a mirrored motor)");
      m.units_per_mps = p.requireDouble("units_per_mps");
      if (m.units_per_mps == 0.0 || !std::isfinite(m.units_per_mps))
        throw robot_core::ParameterError("parameter " + p.qualified("units_per_mps") + " = 0: must be a non-zero number");
      p.describe("max_value", "the clamp of the native value sent");
      m.max_value = p.requireInt("max_value");
      p.requirePositive("max_value", m.max_value);
      p.describe("topic", "the board's command topic out (/hcl/<board>/motor/<motor>/command)");
      m.topic = p.requireString("topic");
      motors_.push_back(std::move(m));
    }
    if (!has_left || !has_right)
      throw robot_core::ParameterError("parameter " + params.qualified("wheels") +
                                       " needs at least one wheel with side: left and one with side: right");
    params.describe("teleop_timeout", "[s] a teleop command drives this long (diff_drive_controller's cmd_vel_timeout)");
    teleop_timeout_ = params.optionalDouble("teleop_timeout", 0.5);
    params.requirePositive("teleop_timeout", teleop_timeout_);
    params.describe("teleop_topic", "the teleop commands in (geometry_msgs/Twist; '': no teleop)");
    teleop_topic_ = params.optionalString("teleop_topic", "/cmd_vel");
  }

  void init(DeviceContext& ctx) override {
    for (Motor& m : motors_) m.pub = ctx.nh.advertise<hcl_drivers::MotorCommand>(m.topic, 1);
    cmd_ = addCommandInput<geometry_msgs::Twist>(ctx.pnh, "cmd_vel", "cmd_vel", Wake::kOnArrival);
    if (!teleop_topic_.empty()) {
      teleop_ = addCommandInput<geometry_msgs::Twist>(ctx.nh, teleop_topic_, "teleop", Wake::kOnArrival);
      match_end_sub_ = ctx.nh.subscribe<std_msgs::Time>("/effectors/match_end", 1, [this](const std_msgs::Time::ConstPtr& m) {
        std::lock_guard<std::mutex> lk(match_mutex_);
        match_end_ = m->data;
      });
    }
    period_ = 1.0 / ctx.rate;
  }

  void refresh() override {
    setAvailable();  // the drive needs no input to be safe: no command means stop
    if (!active()) return;
    auto cmd = cmd_->fresh(cmd_timeout_);
    source_ = cmd ? "cmd_vel" : "none";
    if (teleop_) {
      auto teleop = teleopCommand(cmd != nullptr);
      if (!cmd) cmd = teleop;
    }
    WheelSpeeds target;  // no fresh command: stop (ramped, like any deceleration)
    if (cmd) {
      target = wheelSpeeds(cmd->linear.x, cmd->angular.z, track_width_, wheel_speed_clamp_);
      commanded_ = true;
      last_moving_ = cmd->linear.x != 0.0 || cmd->angular.z != 0.0;
    } else if (commanded_) {
      commanded_ = false;
      ++timeouts_;
      // A commander that stopped and then went quiet (a goal's end) is routine; one that went
      // quiet while the robot was moving is not.
      if (last_moving_)
        ROS_WARN("drive: no cmd_vel for %.2f s while moving, stopping", cmd_timeout_);
      else
        ROS_INFO("drive: no cmd_vel for %.2f s after a stop", cmd_timeout_);
    }
    current_ = rampTowards(current_, target, max_acceleration_, period_);
    send(current_);
  }

  void deactivate() override {
    current_ = WheelSpeeds();
    send(current_);  // at once, without a ramp: this is the emergency path
  }

  void halt() override { deactivate(); }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    stat.addf("left wheel [m/s]", "%.3f", current_.left);
    stat.addf("right wheel [m/s]", "%.3f", current_.right);
    stat.add("command timeouts", timeouts_);
    stat.add("driven by", std::string(source_.load()));
    if (teleop_) {
      stat.add("teleop commands used", teleop_used_);
      stat.add("teleop commands overridden by cmd_vel", teleop_overridden_);
      stat.add("teleop commands ignored in a match", teleop_ignored_);
    }
  }

 private:
  struct Motor {
    bool left = true;
    std::string motor, topic;
    double units_per_mps = 1.0;
    int max_value = 0;
    ros::Publisher pub;
  };

  // The newest teleop command if it is fresh, ~cmd_vel is quiet and no match runs. Every teleop
  // message is counted once: used, overridden by ~cmd_vel, or ignored in a match.
  geometry_msgs::Twist::ConstPtr teleopCommand(bool commanded) {
    const unsigned long n = teleop_->received();
    const unsigned long arrived = n - last_teleop_;
    last_teleop_ = n;
    ros::Time end;
    {
      std::lock_guard<std::mutex> lk(match_mutex_);
      end = match_end_;
    }
    if (!end.isZero() && ros::Time::now() < end) {
      if (arrived > 0) {
        teleop_ignored_ += arrived;
        ROS_WARN_THROTTLE(5.0, "drive: %s ignored: a match is in progress", teleop_->topic().c_str());
      }
      return nullptr;
    }
    if (commanded) {
      teleop_overridden_ += arrived;
      return nullptr;
    }
    auto t = teleop_->fresh(teleop_timeout_);
    if (!t) return t;
    teleop_used_ += arrived;
    source_ = "teleop";
    return t;
  }

  void send(const WheelSpeeds& s) {
    const ros::Time now = ros::Time::now();
    for (auto& m : motors_) {
      hcl_drivers::MotorCommand c;
      c.header.stamp = now;
      c.name = m.motor;
      c.value = nativeValue(m.left ? s.left : s.right, m.units_per_mps, m.max_value);
      m.pub.publish(c);
    }
  }

  std::vector<Motor> motors_;
  std::shared_ptr<LatestValue<geometry_msgs::Twist>> cmd_, teleop_;
  ros::Subscriber match_end_sub_;
  std::mutex match_mutex_;
  ros::Time match_end_;     // the running match's end (zero: no match armed)
  unsigned long last_teleop_ = 0;
  unsigned long teleop_used_ = 0, teleop_ignored_ = 0, teleop_overridden_ = 0;
  std::atomic<const char*> source_{"none"};  // what drives now; read by diagnose()
  double teleop_timeout_ = 0.5;
  std::string teleop_topic_;
  WheelSpeeds current_;
  double track_width_ = 0.0, wheel_speed_clamp_ = 0.0, max_acceleration_ = 0.0, cmd_timeout_ = 0.3, period_ = 0.02;
  unsigned long timeouts_ = 0;
  bool commanded_ = false;
  bool last_moving_ = false;  // the last fresh command asked for motion
};

}  // namespace hal_nodes

HAL_EXPORT_DEVICE(DifferentialDrive, DifferentialDrive,
                  "Differential-drive effector: cmd_vel to per-wheel motor commands in each board's native unit.")
