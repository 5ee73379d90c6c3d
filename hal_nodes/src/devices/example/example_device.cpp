// ExampleDevice: the skeleton's device. Turns the example board's dial ADC into a position
// 0..1 and drives the board's lamp from a brightness 0..1. An Effector: deactivation turns
// the lamp off and ignores brightness commands. Copy this file to start a new device.
// ~warn_above shows how a device raises its level on /diagnostics (setCondition).
//
// Parameters: read and described in configure() (the table: hal_nodes/PARAMETERS.md, make docs).
// Topics: ~reading (hal_nodes/ExampleReading, out), ~lamp (std_msgs/Float64 brightness, in).
#include <hal_nodes/ExampleReading.h>
#include <hcl_drivers/ExampleBoardState.h>
#include <std_msgs/Float64.h>
#include <std_msgs/UInt8.h>

#include <algorithm>
#include <cmath>

#include "hal_nodes/device_nodelet.h"

namespace hal_nodes {

class ExampleDevice : public Effector {
 public:
  void configure(const robot_core::Params& params) override {
    params.describe("max_input_age", "[s] older board data makes the device unavailable");
    max_input_age_ = params.optionalDouble("max_input_age", 0.5);
    params.requirePositive("max_input_age", max_input_age_);
    params.describe("max_command_age", "[s] an older brightness command is dropped, lamp off");
    max_command_age_ = params.optionalDouble("max_command_age", 0.5);
    params.requirePositive("max_command_age", max_command_age_);
    params.describe("warn_above", "dial position above which the device is WARN on /diagnostics (1: never)");
    warn_above_ = params.optionalDouble("warn_above", 1.0);
    params.requireInRange("warn_above", warn_above_, 0.0, 1.0);
    params.describe("board_state", "the board's state topic in (hcl_drivers/ExampleBoardState)");
    board_state_topic_ = params.optionalString("board_state", "/hcl/example_board/state");
    params.describe("board_lamp", "the board's lamp command topic out (std_msgs/UInt8)");
    board_lamp_topic_ = params.optionalString("board_lamp", "/hcl/example_board/lamp_pwm");
  }

  void init(DeviceContext& ctx) override {
    board_ = addInput<hcl_drivers::ExampleBoardState>(ctx.nh, board_state_topic_, "board");
    brightness_ = addCommandInput<std_msgs::Float64>(ctx.pnh, "lamp", "lamp command");
    lamp_pub_ = ctx.nh.advertise<std_msgs::UInt8>(board_lamp_topic_, 1);
    reading_pub_ = ctx.pnh.advertise<ExampleReading>("reading", 1);
  }

  void refresh() override {
    const auto board = board_->fresh(max_input_age_);
    if (!board) {
      setUnavailable("no fresh data from the example board (input age " + std::to_string(board_->age()) + " s)");
    } else {
      setAvailable();
      ExampleReading r;
      r.header.stamp = board->header.stamp;
      r.position = static_cast<double>(board->dial_raw) / 1023.0;
      r.input_age = (ros::Time::now() - board->header.stamp).toSec();
      reading_pub_.publish(r);
      if (r.position > warn_above_)
        setCondition(diagnostic_msgs::DiagnosticStatus::WARN, "dial at " + std::to_string(r.position) + ", above " +
                                                                  std::to_string(warn_above_));
      else
        clearCondition();
    }
    if (!active()) return;  // deactivated: deactivate() switched the lamp off, stay quiet
    const auto cmd = brightness_->fresh(max_command_age_);
    // No recent command: lamp off (the board's own command timeout would do it too).
    publishLamp(cmd ? cmd->data : 0.0);
  }

  void deactivate() override { publishLamp(0.0); }

 private:
  void publishLamp(double brightness) {
    if (!std::isfinite(brightness)) brightness = 0.0;
    std_msgs::UInt8 pwm;
    pwm.data = static_cast<uint8_t>(std::lround(255.0 * std::clamp(brightness, 0.0, 1.0)));
    lamp_pub_.publish(pwm);
  }

  std::shared_ptr<LatestValue<hcl_drivers::ExampleBoardState>> board_;
  std::shared_ptr<LatestValue<std_msgs::Float64>> brightness_;
  ros::Publisher lamp_pub_;
  ros::Publisher reading_pub_;
  std::string board_state_topic_, board_lamp_topic_;
  double max_input_age_ = 0.5;
  double max_command_age_ = 0.5;
  double warn_above_ = 1.0;
};

}  // namespace hal_nodes

HAL_EXPORT_DEVICE(ExampleDevice, ExampleDevice,
                  "Skeleton example device: dial position from the example board, lamp brightness back to it.")
