// The nodelet that hosts one Device: validates ~rate, runs refresh() at that rate (and when a
// waking input arrives, paced by robot_core::LoopPacer so ~max_rate stays a ceiling), follows
// /effectors/deactivated for effectors, and reports on /diagnostics: rate achieved, the
// sample age of every input, and why the device is unavailable.
//
// Common parameters of every device: read and described in DeviceSettings::read()
// (the table: hal_nodes/PARAMETERS.md, make docs). ~max_rate paces as robot_core/loop_pacer.h
// says, ~diagnostic_period as robot_core/diagnostic_reporter.h; ~required is published as the
// `required` value of the device's status.
#pragma once

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <robot_core/configurable_component.h>
#include <robot_core/diagnostic_reporter.h>
#include <robot_core/loop_pacer.h>
#include <robot_core/priority_inheritance_mutex.h>
#include <robot_core/rate_meter.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <std_msgs/Bool.h>

#include <memory>
#include <mutex>

#include "hal_nodes/device.h"
#include "hal_nodes/effector.h"

namespace hal_nodes {

// The parameters every device has, read by the framework (see above).
struct DeviceSettings {
  double rate = 0.0;
  double max_rate = 0.0;
  double diagnostic_period = 1.0;
  double startup_grace = 5.0;
  bool required = true;

  static DeviceSettings read(const robot_core::Params& params);
};

class DeviceNodeletBase : public nodelet::Nodelet, public robot_core::ConfigurableComponent {
 public:
  ~DeviceNodeletBase() override;
  // The common parameters and the device's own, over `params` (check_config, with no master).
  void readConfig(const robot_core::Params& params, const robot_core::RobotGeometry& robot) const override;

 protected:
  virtual std::unique_ptr<Device> createDevice() const = 0;

 private:
  void onInit() final;
  void onTimer(const ros::TimerEvent& e);
  void wake(const ros::Time& stamp);  // a Wake::kOnArrival input arrived, stamped `stamp` (zero: none)
  void onGathered(const ros::TimerEvent& e);  // a woken refresh, after the gathering delay
  void restartGatherTimer(double delay);
  void refreshIfDue(bool tick);     // runs refresh() when the pacer allows it (tick: for the periodic timer)
  void onDeactivated(const std_msgs::Bool::ConstPtr& msg);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);

  std::unique_ptr<Device> device_;
  Effector* effector_ = nullptr;  // device_ when it is an effector
  std::unique_ptr<robot_core::DiagnosticReporter> reporter_;  // checks on ROS time: the simulated clock
  ros::Timer refresh_timer_;  // ticks at ~rate; a tick runs refresh() when the pacer says it is due
  // Shared by the real-time refreshes and normal-priority threads (inputs, the diagnostics'
  // checks): priority inheritance, so a refresh never waits behind a preempted normal thread.
  robot_core::PriorityInheritanceMutex pace_mutex_;
  robot_core::LoopPacer pacer_{1.0};
  ros::Timer gather_timer_;  // one-shot: a woken refresh, once the waking inputs pause (or a token is there)
  bool wake_posted_ = false;     // gather_timer_ is running...
  bool gathering_ = false;       // ...for a burst of inputs (false: for the pacer's next token)
  ros::Time gather_started_;
  unsigned long woken_refreshes_ = 0, wakes_deferred_ = 0;
  ros::Time newest_woken_stamp_;  // of the newest input that woke a refresh
  bool initialized_ = false;   // init() done: inputs may wake refresh()
  bool shutting_down_ = false;
  ros::Subscriber deactivated_sub_;
  double rate_ = 0.0;
  double max_rate_ = 0.0;  // ~max_rate: the ceiling of woken runs
  // Start-up: a device whose inputs have not arrived yet within ~startup_grace of its start is
  // "starting" (WARN), not a fault; once it has worked, or after the grace, unavailable is ERROR.
  double startup_grace_ = 5.0;  // [s, ROS time]
  bool required_ = true;
  ros::Time started_;
  bool ever_available_ = false;  // latched by the diagnostics' checks (20 Hz)

  std::mutex refresh_mutex_;  // refresh() and deactivate() never interleave
  mutable robot_core::PriorityInheritanceMutex stats_mutex_;  // refreshes vs the diagnostics' checks
  robot_core::RateMeter meter_;
  unsigned long refresh_errors_ = 0;
  std::string last_error_;
};

template <class DeviceT>
class DeviceNodelet : public DeviceNodeletBase {
 protected:
  std::unique_ptr<Device> createDevice() const override { return std::make_unique<DeviceT>(); }
};

}  // namespace hal_nodes

// Export a device class as nodelet plugin "hal_nodes/<Type>", the `type` of its config block:
//   HAL_EXPORT_DEVICE(MyDevice, MyType, "one line for `rosrun nodelet declared_nodelets`");
// at the start of a line, the description without double quotes. The build writes
// nodelet_plugins.xml from these lines (hcl_drivers' cmake/generate_plugin_xml.cmake).
#define HAL_EXPORT_DEVICE(DeviceName, Type, Description)                                \
  namespace hal_nodes {                                                                 \
  using DeviceName##Nodelet = DeviceNodelet<DeviceName>;                                \
  }                                                                                     \
  PLUGINLIB_EXPORT_CLASS(hal_nodes::DeviceName##Nodelet, nodelet::Nodelet)
