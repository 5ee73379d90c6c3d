// The Device: what every HAL device implements (configure, init, refresh, halt).
// A device turns raw board values into physical meaning and offers a hardware-independent
// interface to the brain. The framework (DeviceNodelet) calls:
//   configure(params)  first: read every ~parameter into members (robot_core/params.h) and
//               throw robot_core::ParameterError for a bad one. Nothing else: check_config runs
//               it over a config file with no master, and calls every key it never asked for unknown.
//               The object itself is built there too, with no ros::init: no ros::NodeHandle (or
//               a tf listener) as a member constructed with the device; make those in init().
//               robot() is the robot's description (/robot: radius, track width, ..) by then.
//   init(ctx)   once, after configure(): declare inputs with addInput(), advertise outputs.
//   refresh()   at the configured ~rate on the nodelet callback queue: sample the newest
//               inputs, compute, publish. Call setUnavailable("why") when it cannot. An input
//               declared Wake::kOnArrival also runs it as soon as a message arrives, within
//               the same rate ceiling (robot_core/loop_pacer.h): for readings that matter at
//               once, such as a ranger or a velocity command.
//   halt()      on shutdown.
// The device's /diagnostics level comes from the framework (inputs, rate, availability); a device
// raises it with setCondition(WARN or ERROR, "why") while something deserves a look although the
// device still works (a temperature above its limit), and clearCondition() when it passes.
#pragma once

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <robot_core/params.h>
#include <robot_core/priority_inheritance_mutex.h>
#include <robot_core/robot_geometry.h>
#include <ros/ros.h>

#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "hal_nodes/latest_value.h"

namespace hal_nodes {

struct DeviceContext {
  ros::NodeHandle nh;   // the HAL process namespace (global topics)
  ros::NodeHandle pnh;  // the device's private namespace
  std::string name;     // e.g. "/hal/example_device"
  double rate = 0.0;    // configured refresh rate [Hz], validated
};

// Whether a new message on an input runs the device's refresh at once or waits for its tick.
enum class Wake { kOnTick, kOnArrival };

class Device {
 public:
  virtual ~Device() = default;

  virtual void configure(const robot_core::Params& params) = 0;
  virtual void init(DeviceContext& ctx) = 0;
  virtual void refresh() = 0;
  virtual void halt() {}
  virtual void diagnose(diagnostic_updater::DiagnosticStatusWrapper& /*stat*/) {}

  // Framework side: how an arriving Wake::kOnArrival input runs refresh() (set before init()),
  // inputs for diagnostics, and whether the device is usable.
  void setWakeHandler(std::function<void(const ros::Time& stamp)> wake) { wake_ = std::move(wake); }
  void setRobot(const robot_core::RobotGeometry& robot) { robot_ = robot; }
  const std::vector<std::shared_ptr<InputStatus>>& inputs() const { return inputs_; }
  bool available(std::string* reason) const {
    std::lock_guard lk(status_mutex_);
    if (reason) *reason = unavailable_reason_;
    return unavailable_reason_.empty();
  }
  // The condition set by the device: its level (OK when none) and message.
  uint8_t condition(std::string* message) const {
    std::lock_guard lk(status_mutex_);
    if (message) *message = condition_message_;
    return condition_level_;
  }

 protected:
  // The robot's description (/robot), read once by the framework before configure().
  const robot_core::RobotGeometry& robot() const { return robot_; }

  // Subscribe to an input topic in the pull model; `name` labels it on /diagnostics.
  template <class M>
  std::shared_ptr<LatestValue<M>> addInput(ros::NodeHandle& nh, const std::string& topic, const std::string& name,
                                           Wake wake = Wake::kOnTick) {
    typename LatestValue<M>::OnArrival on_arrival;
    if (wake == Wake::kOnArrival && wake_) on_arrival = wake_;
    auto input = std::make_shared<LatestValue<M>>(nh, topic, name, on_arrival);
    inputs_.push_back(input);
    return input;
  }

  // A command input (velocity, lamp, ...): like addInput, and a sender outside the robot's
  // network is not obeyed during a match (robot_core/command_gate.h).
  template <class M>
  std::shared_ptr<LatestValue<M>> addCommandInput(ros::NodeHandle& nh, const std::string& topic, const std::string& name,
                                                  Wake wake = Wake::kOnTick) {
    typename LatestValue<M>::OnArrival on_arrival;
    if (wake == Wake::kOnArrival && wake_) on_arrival = wake_;
    auto input = std::make_shared<LatestValue<M>>(nh, topic, name, on_arrival, true);
    inputs_.push_back(input);
    return input;
  }

  // For a device that subscribes on its own (a queue of every message, not addInput's newest
  // value): a message stamped `stamp` arrived that should run refresh() at once, as a
  // Wake::kOnArrival input does.
  void wakeRefresh(const ros::Time& stamp) {
    if (wake_) wake_(stamp);
  }

  void setAvailable() { setUnavailable(""); }
  void setUnavailable(const std::string& reason) {
    std::lock_guard lk(status_mutex_);
    unavailable_reason_ = reason;
  }

  // Raise the device's /diagnostics level (diagnostic_msgs::DiagnosticStatus::WARN or ERROR) with
  // `message` (it replaces "ok", or joins the framework's own complaint after a "; "), until
  // clearCondition(). It does not make the device unavailable. Thread-safe.
  void setCondition(uint8_t level, const std::string& message) {
    std::lock_guard lk(status_mutex_);
    condition_level_ = level;
    condition_message_ = message;
  }
  void clearCondition() { setCondition(diagnostic_msgs::DiagnosticStatus::OK, ""); }

 private:
  robot_core::RobotGeometry robot_;
  std::vector<std::shared_ptr<InputStatus>> inputs_;
  std::function<void(const ros::Time& stamp)> wake_;
  mutable robot_core::PriorityInheritanceMutex status_mutex_;  // device loop vs callbacks and checks
  std::string unavailable_reason_ = "not refreshed yet";
  uint8_t condition_level_ = diagnostic_msgs::DiagnosticStatus::OK;
  std::string condition_message_;
};

}  // namespace hal_nodes
