// Joystick: a hardware-independent gamepad. The board's sensor_msgs/Joy (/hcl/<board>/joy,
// indices of one particular pad) becomes named axes and buttons from config, published as
// hal_nodes/JoystickState on ~state, and every button edge as hal_nodes/JoystickEvent on
// ~events (/hal/joystick/events) that the brain registers callbacks on. Axes get a dead zone
// (rescaled so the output stays continuous) and optional inversion.
// When the pad goes stale every held button is released (an event each) and the axes read
// 0: a dead-man button held when the cable came out must not stay held.
// The device samples the pad at ~rate: a tap shorter than one period can be missed, so run
// it at the board's rate (50 Hz is plenty for a hand).
//
// Parameters: read and described in configure() (the table: hal_nodes/PARAMETERS.md, make docs).
#include <hal_nodes/JoystickEvent.h>
#include <hal_nodes/JoystickState.h>
#include <sensor_msgs/Joy.h>

#include <algorithm>
#include <cmath>

#include "hal_nodes/device_nodelet.h"
#include <robot_core/params.h>

namespace hal_nodes {

class JoystickDevice : public Device {
 public:
  void configure(const robot_core::Params& params) override {
    params.describe("axes", "name: index in the pad's Joy axes (at least one axis or button overall)");
    axes_ = params.optionalIntMap("axes");
    params.describe("buttons", "name: index in the pad's Joy buttons");
    buttons_ = params.optionalIntMap("buttons");
    if (axes_.empty() && buttons_.empty())
      throw robot_core::ParameterError("parameters " + params.qualified("axes") + " / " + params.qualified("buttons") +
                                       ": name at least one axis or button (name: index)");
    params.describe("inverted_axes", "names of the axes whose sign flips");
    const auto inverted = params.optionalStringList("inverted_axes", {});
    for (const auto& n : inverted) {
      if (std::none_of(axes_.begin(), axes_.end(), [&](const auto& a) { return a.first == n; }))
        throw robot_core::ParameterError("parameter " + params.qualified("inverted_axes") + ": '" + n +
                                         "' is not one of ~axes");
    }
    invert_.clear();
    for (const auto& a : axes_) invert_.push_back(std::find(inverted.begin(), inverted.end(), a.first) != inverted.end());
    params.describe("dead_zone", "axis values within it read 0; the rest is rescaled to stay continuous");
    dead_zone_ = params.optionalDouble("dead_zone", 0.05);
    params.requireInRange("dead_zone", dead_zone_, 0.0, 0.9);
    params.describe("max_input_age", "[s] an older Joy makes the pad stale: buttons released, axes 0");
    max_input_age_ = params.optionalDouble("max_input_age", 0.5);
    params.requirePositive("max_input_age", max_input_age_);
    held_.assign(buttons_.size(), false);
    params.describe("joy", "the pad's input topic (sensor_msgs/Joy, /hcl/<board>/joy)");
    joy_topic_ = params.requireString("joy");
  }

  void init(DeviceContext& ctx) override {
    joy_ = addInput<sensor_msgs::Joy>(ctx.nh, joy_topic_, "joy");
    state_pub_ = ctx.pnh.advertise<JoystickState>("state", 1);
    event_pub_ = ctx.pnh.advertise<JoystickEvent>("events", 50);
  }

  void refresh() override {
    const auto joy = joy_->fresh(max_input_age_);
    JoystickState s;
    s.header.stamp = joy ? joy->header.stamp : ros::Time::now();
    for (const auto& a : axes_) s.axis_names.push_back(a.first);
    for (const auto& b : buttons_) s.button_names.push_back(b.first);
    std::string missing;
    for (std::size_t i = 0; i < axes_.size(); ++i) {
      double v = 0.0;
      if (joy && axes_[i].second < static_cast<int>(joy->axes.size())) v = shape(joy->axes[axes_[i].second]) * (invert_[i] ? -1 : 1);
      else if (joy) missing += " axis " + axes_[i].first;
      s.axes.push_back(v);
    }
    for (std::size_t i = 0; i < buttons_.size(); ++i) {
      bool pressed = false;
      if (joy && buttons_[i].second < static_cast<int>(joy->buttons.size())) pressed = joy->buttons[buttons_[i].second] != 0;
      else if (joy) missing += " button " + buttons_[i].first;
      s.buttons.push_back(pressed);
      if (pressed != held_[i]) {
        JoystickEvent e;
        e.header.stamp = s.header.stamp;
        e.button = buttons_[i].first;
        e.pressed = pressed;
        event_pub_.publish(e);
        held_[i] = pressed;
      }
    }
    if (!joy) {
      setUnavailable("no fresh joystick state (age " + std::to_string(joy_->age()) + " s): buttons released, axes 0");
      return;
    }
    if (!missing.empty()) setUnavailable("the pad does not have the configured" + missing);
    else setAvailable();
    state_pub_.publish(s);
  }

 private:
  double shape(double v) const {
    if (!std::isfinite(v)) return 0.0;
    v = std::clamp(v, -1.0, 1.0);
    if (std::abs(v) <= dead_zone_) return 0.0;
    return std::copysign((std::abs(v) - dead_zone_) / (1.0 - dead_zone_), v);
  }

  std::vector<std::pair<std::string, int>> axes_, buttons_;
  std::vector<bool> invert_, held_;
  std::shared_ptr<LatestValue<sensor_msgs::Joy>> joy_;
  ros::Publisher state_pub_, event_pub_;
  std::string joy_topic_;
  double dead_zone_ = 0.05, max_input_age_ = 0.5;
};

}  // namespace hal_nodes

HAL_EXPORT_DEVICE(JoystickDevice, Joystick,
                  "Joystick: named axes and buttons with edge events, independent of the pad.")
