// BallHarvester: Logion's (2008) ball roller. The brain sets a speed -1..1 on ~speed
// (std_msgs/Float64, latched: a setting, not a stream; /hal/harvester/speed): forward
// swallows balls, backward unloads them. The effector sends the roller motor an
// hcl_drivers/MotorCommand at ~rate (so the board's command timeout only stops it when HAL
// dies). Deactivation stops the roller at once and ignores ~speed until reactivated.
// With ~ball_sensor configured (the throat sensor a swallowed ball passes), ~ball_present
// (std_msgs/Bool) says a ball is in the mouth, and ~held (std_msgs/Int32, latched) counts what the
// harvester holds: one more for each ball that passes the sensor while the roller swallows,
// none once the roller has unloaded for ~empty_after [s].
//
// Parameters: read and described in configure() (the table: hal_nodes/PARAMETERS.md, make docs).
#include <hcl_drivers/MotorCommand.h>
#include <std_msgs/Bool.h>
#include <std_msgs/Float64.h>
#include <std_msgs/Int32.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "hal_nodes/device_nodelet.h"
#include "hal_nodes/devices/contact_input.h"

namespace hal_nodes {

class BallHarvester : public Effector {
 public:
  void configure(const robot_core::Params& params) override {
    params.describe("motor", "the MotorCommand's name");
    motor_ = params.optionalString("motor", "roller");
    params.describe("max_value",
                    "native command at speed 1, not 0 (e.g. HBmotor duty 127; negative reverses the roller)");
    max_value_ = params.requireInt("max_value");
    if (max_value_ == 0)
      throw robot_core::ParameterError("parameter " + params.qualified("max_value") + " = 0: must be non-zero");
    params.describe("motor_topic", "the roller's command topic out (/hcl/<board>/motor/<name>/command)");
    motor_topic_ = params.requireString("motor_topic");
    sensor_.reset();
    params.describe("ball_sensor", "the throat switch a swallowed ball passes (contact_input.h); optional");
    if (params.has("ball_sensor")) {
      sensor_ = ContactSpec::read(params, "ball_sensor");
      params.describe("empty_after", "[s] of unloading after which nothing is held (with ball_sensor)");
      empty_after_ = params.optionalDouble("empty_after", 1.5);
      params.requirePositive("empty_after", empty_after_);
    } else {
      params.unused("empty_after");  // meaningful only with a ball sensor
    }
  }

  void init(DeviceContext& ctx) override {
    using namespace hcl_drivers;  // the boards' messages
    motor_pub_ = ctx.nh.advertise<MotorCommand>(motor_topic_, 1);
    speed_ = addCommandInput<std_msgs::Float64>(ctx.pnh, "speed", "speed");
    if (sensor_) {
      sensor_input_ = addInput<DigitalInputs>(ctx.nh, sensor_->topic, "ball sensor");
      ball_pub_ = ctx.pnh.advertise<std_msgs::Bool>("ball_present", 1);
      held_pub_ = ctx.pnh.advertise<std_msgs::Int32>("held", 1, true);
      publishHeld();
    }
  }

  void refresh() override {
    setAvailable();
    if (sensor_) {
      const auto m = sensor_input_->fresh(0.5);
      const auto closed = m ? sensor_->closed(*m) : std::nullopt;
      if (!closed) {
        setUnavailable("ball sensor " + sensor_->topic + " not fresh");
      } else {
        std_msgs::Bool b;
        b.data = *closed;
        ball_pub_.publish(b);
        count(*closed);
      }
    }
    if (!active()) return;
    const auto s = speed_->newest();
    double v = s && std::isfinite(s->data) ? std::clamp(s->data, -1.0, 1.0) : 0.0;
    send(v);
  }

  void deactivate() override { send(0.0); }
  void halt() override { send(0.0); }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    stat.add("roller command", last_);
    if (sensor_) stat.add("balls held", held_.load());
  }

 private:
  void send(double v) {
    hcl_drivers::MotorCommand c;
    c.header.stamp = ros::Time::now();
    c.name = motor_;
    c.value = static_cast<int>(std::lround(v * max_value_));
    last_ = c.value;
    speed_now_ = v;
    motor_pub_.publish(c);
  }

  // What it holds: a ball passing the sensor while the roller swallows is one more; a long
  // enough unload leaves none.
  void count(bool ball) {
    const ros::Time now = ros::Time::now();
    int held = held_;
    if (ball && !ball_before_ && speed_now_ > 0.1) ++held;
    ball_before_ = ball;
    if (speed_now_ < -0.1) {
      if (unloading_since_.isZero()) unloading_since_ = now;
      if ((now - unloading_since_).toSec() >= empty_after_) held = 0;
    } else {
      unloading_since_ = ros::Time();
    }
    if (held != held_) {
      held_ = held;
      publishHeld();
    }
  }

  void publishHeld() {
    std_msgs::Int32 m;
    m.data = held_;
    held_pub_.publish(m);
  }

  std::string motor_, motor_topic_;
  int max_value_ = 0, last_ = 0;
  std::atomic<int> held_{0};  // read by diagnose() on the diagnostics thread
  bool ball_before_ = false;
  double speed_now_ = 0.0;  // the roller's speed -1..1 as last sent
  ros::Time unloading_since_;
  double empty_after_ = 1.5;
  ros::Publisher motor_pub_, ball_pub_, held_pub_;
  std::shared_ptr<LatestValue<std_msgs::Float64>> speed_;
  std::optional<ContactSpec> sensor_;
  std::shared_ptr<LatestValue<hcl_drivers::DigitalInputs>> sensor_input_;
};

}  // namespace hal_nodes

HAL_EXPORT_DEVICE(BallHarvester, BallHarvester,
                  "2008 ball harvester: roller speed effector with an optional ball sensor.")
