// BallHarvester: Logion's (2008) ball roller. The brain sets a speed -1..1 on ~speed
// (std_msgs/Float64, latched: a setting, not a stream; /hal/harvester/speed): forward
// swallows balls, backward unloads them. The effector sends the roller motor an
// hcl_drivers/MotorCommand at ~rate (so the board's command timeout only stops it when HAL
// dies). Deactivation stops the roller at once and ignores ~speed until reactivated.
// With ~ball_sensor configured, ~ball_present (std_msgs/Bool) says a ball is in the mouth.
//
// Parameters (besides ~rate):
//   ~motor_topic   the roller's command topic (/hcl/<board>/motor/<name>/command), required
//   ~motor         MotorCommand.name (default roller)
//   ~max_value     native command at speed 1 (e.g. HBmotor duty 127; sign flips), required, != 0
//   ~ball_sensor   contact (contact_input.h), optional
#include <hcl_drivers/MotorCommand.h>
#include <std_msgs/Bool.h>
#include <std_msgs/Float64.h>

#include <algorithm>
#include <cmath>

#include "hal_nodes/device_nodelet.h"
#include "hal_nodes/devices/contact_input.h"

namespace hal_nodes {

class BallHarvester : public Effector {
 public:
  void init(DeviceContext& ctx) override {
    using namespace hcl_drivers;  // the boards' messages
    motor_ = optionalString(ctx.pnh, "motor", "roller");
    max_value_ = requireInt(ctx.pnh, "max_value");
    if (max_value_ == 0) throw ParameterError("parameter " + qualified(ctx.pnh, "max_value") + " = 0: must be non-zero");
    motor_pub_ = ctx.nh.advertise<MotorCommand>(requireString(ctx.pnh, "motor_topic"), 1);
    speed_ = addCommandInput<std_msgs::Float64>(ctx.pnh, "speed", "speed");
    if (ctx.pnh.hasParam("ball_sensor")) {
      sensor_ = ContactSpec::read(ctx.pnh, "ball_sensor");
      sensor_input_ = addInput<DigitalInputs>(ctx.nh, sensor_->topic, "ball sensor");
      ball_pub_ = ctx.pnh.advertise<std_msgs::Bool>("ball_present", 1);
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
      }
    }
    if (!active()) return;
    const auto s = speed_->newest();
    double v = s && std::isfinite(s->data) ? std::clamp(s->data, -1.0, 1.0) : 0.0;
    send(v);
  }

  void deactivate() override { send(0.0); }
  void halt() override { send(0.0); }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override { stat.add("roller command", last_); }

 private:
  void send(double v) {
    hcl_drivers::MotorCommand c;
    c.header.stamp = ros::Time::now();
    c.name = motor_;
    c.value = static_cast<int>(std::lround(v * max_value_));
    last_ = c.value;
    motor_pub_.publish(c);
  }

  std::string motor_;
  int max_value_ = 0, last_ = 0;
  ros::Publisher motor_pub_, ball_pub_;
  std::shared_ptr<LatestValue<std_msgs::Float64>> speed_;
  std::optional<ContactSpec> sensor_;
  std::shared_ptr<LatestValue<hcl_drivers::DigitalInputs>> sensor_input_;
};

}  // namespace hal_nodes

HAL_EXPORT_DEVICE(BallHarvester, BallHarvester,
                  "2008 ball harvester: roller speed effector with an optional ball sensor.")
