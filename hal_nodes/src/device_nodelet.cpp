#include "hal_nodes/device_nodelet.h"

#include <diagnostic_msgs/DiagnosticStatus.h>

#include <chrono>
#include <cmath>

namespace hal_nodes {

using diagnostic_msgs::DiagnosticStatus;
using robot_core::optionalDouble;
using robot_core::requireDouble;
using robot_core::requirePositive;

DeviceNodeletBase::~DeviceNodeletBase() {
  refresh_timer_.stop();
  diagnostic_timer_.stop();
  deactivated_sub_.shutdown();
  std::lock_guard<std::mutex> lk(refresh_mutex_);
  if (device_) {
    try {
      device_->halt();
    } catch (const std::exception& e) {
      ROS_ERROR("%s: halt() failed on shutdown: %s", getName().c_str(), e.what());
    }
  }
}

void DeviceNodeletBase::onInit() {
  ros::NodeHandle& pnh = getPrivateNodeHandle();
  try {
    DeviceContext ctx{getNodeHandle(), pnh, getName(), 0.0};
    ctx.rate = requireDouble(pnh, "rate");
    requirePositive(pnh, "rate", ctx.rate);
    rate_ = ctx.rate;
    const double diagnostic_period = optionalDouble(pnh, "diagnostic_period", 0.25);
    requirePositive(pnh, "diagnostic_period", diagnostic_period);
    pnh.setParam("diagnostic_period", diagnostic_period);
    startup_grace_ = optionalDouble(pnh, "startup_grace", 5.0);
    robot_core::requireInRange(pnh, "startup_grace", startup_grace_, 0.0, 600.0);
    required_ = robot_core::optionalBool(pnh, "required", true);
    started_ = ros::Time::now();

    device_ = createDevice();
    device_->init(ctx);
    effector_ = dynamic_cast<Effector*>(device_.get());

    updater_ = std::make_unique<diagnostic_updater::Updater>(getNodeHandle(), pnh, getName());
    updater_->setHardwareID(getName());
    updater_->add("device", this, &DeviceNodeletBase::diagnose);
    diagnostic_timer_ = getNodeHandle().createTimer(ros::Duration(0.05), [this](const ros::TimerEvent&) {
      updater_->update();
    });
    if (effector_)
      deactivated_sub_ = getNodeHandle().subscribe("/effectors/deactivated", 1, &DeviceNodeletBase::onDeactivated, this);
    refresh_timer_ = getNodeHandle().createTimer(ros::Duration(1.0 / rate_), &DeviceNodeletBase::onTimer, this);
    NODELET_INFO("device %s refreshing at %.1f Hz%s", getName().c_str(), rate_, effector_ ? " (effector)" : "");
  } catch (const robot_core::ParameterError& e) {
    NODELET_FATAL("%s", e.what());
    throw;
  } catch (const std::exception& e) {
    NODELET_FATAL("device %s failed to start: %s", getName().c_str(), e.what());
    throw;
  }
}

void DeviceNodeletBase::onTimer(const ros::TimerEvent& e) {
  const auto wall_start = std::chrono::steady_clock::now();
  std::string error;
  {
    std::lock_guard<std::mutex> lk(refresh_mutex_);
    try {
      device_->refresh();
    } catch (const std::exception& ex) {
      error = ex.what();
    }
  }
  const double busy = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  std::lock_guard<std::mutex> lk(stats_mutex_);
  meter_.tick(e.current_real.toSec(), busy);
  if (!error.empty()) {
    ++refresh_errors_;
    last_error_ = error;
    NODELET_ERROR_THROTTLE(1.0, "%s: refresh() failed: %s", getName().c_str(), error.c_str());
  }
}

void DeviceNodeletBase::onDeactivated(const std_msgs::Bool::ConstPtr& msg) {
  std::lock_guard<std::mutex> lk(refresh_mutex_);
  if (msg->data == !effector_->active()) return;
  effector_->setActive(!msg->data);
  NODELET_WARN("%s %s", getName().c_str(), msg->data ? "deactivated" : "reactivated");
}

void DeviceNodeletBase::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  std::string reason;
  const bool available = device_->available(&reason);
  const ros::Time now = ros::Time::now();
  {
    std::lock_guard<std::mutex> lk(stats_mutex_);
    const double achieved = meter_.rate();
    ever_available_ = ever_available_ || available;
    if (!available && !ever_available_ && (now - started_).toSec() < startup_grace_) {
      stat.summaryf(DiagnosticStatus::WARN, "starting: %s", reason.c_str());
    } else if (!available) {
      stat.summaryf(DiagnosticStatus::ERROR, "unavailable: %s", reason.c_str());
    } else if (effector_ && !effector_->active()) {
      stat.summary(DiagnosticStatus::WARN, "deactivated");
    } else if (meter_.count() > 2 && achieved < 0.8 * rate_) {
      stat.summaryf(DiagnosticStatus::WARN, "refreshing at %.1f Hz, configured %.1f Hz", achieved, rate_);
    } else {
      stat.summary(DiagnosticStatus::OK, "ok");
    }
    std::string condition;
    const uint8_t condition_level = device_->condition(&condition);
    if (condition_level != DiagnosticStatus::OK) stat.mergeSummary(condition_level, condition);
    stat.add("required", required_ ? "true" : "false");  // readiness waits only for required devices
    stat.addf("configured rate [Hz]", "%.2f", rate_);
    stat.addf("achieved rate [Hz]", "%.2f", achieved);
    stat.addf("mean refresh time [ms]", "%.3f", 1e3 * meter_.meanBusy());
    stat.add("refresh errors", refresh_errors_);
    stat.add("last error", last_error_);
  }
  for (const auto& in : device_->inputs()) {
    const double age = in->age(now);
    stat.addf("input " + in->name() + " age [s]", std::isfinite(age) ? "%.3f" : "never received (%.0f)", age);
    stat.add("input " + in->name() + " topic", in->topic());
  }
  if (effector_) stat.add("active", effector_->active());
  device_->diagnose(stat);
}

}  // namespace hal_nodes
