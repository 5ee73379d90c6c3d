#include "hal_nodes/device_nodelet.h"

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <robot_core/realtime.h>

#include <chrono>
#include <cmath>

namespace hal_nodes {

namespace {
constexpr double kGatherQuiet = 0.001;  // [s, ROS time, like the pacer and the HCL's command gathering]
constexpr double kGatherLimit = 0.004;  // [s, ROS time]
}  // namespace

using diagnostic_msgs::DiagnosticStatus;

DeviceSettings DeviceSettings::read(const robot_core::Params& p) {
  DeviceSettings s;
  p.describe("rate", "[Hz] how often refresh() runs");
  s.rate = p.requireDouble("rate");
  p.requirePositive("rate", s.rate);
  // The ceiling of the runs that inputs wake (robot_core/loop_pacer.h): above the rate of the
  // streams that wake the device, or each of their readings ends up waiting for its token.
  p.describe("max_rate",
             "[Hz] the ceiling of the refreshes inputs wake: set it above the rate of the streams that wake it");
  s.max_rate = p.optionalDouble("max_rate", s.rate);
  p.requireInRange("max_rate", s.max_rate, s.rate, 10.0 * s.rate);
  p.describe("diagnostic_period", "[s] status published this often while its level stays, at once when it changes");
  s.diagnostic_period = p.optionalDouble("diagnostic_period", 1.0);
  p.requirePositive("diagnostic_period", s.diagnostic_period);
  p.describe("startup_grace", "[s] unavailable within this of the start is WARN (starting), not ERROR");
  s.startup_grace = p.optionalDouble("startup_grace", 5.0);
  p.requireInRange("startup_grace", s.startup_grace, 0.0, 600.0);
  p.describe("required", "false: an optional device (the joystick's) the brain's readiness does not wait for");
  s.required = p.optionalBool("required", true);
  return s;
}

void DeviceNodeletBase::readConfig(const robot_core::Params& params, const robot_core::RobotGeometry& robot) const {
  DeviceSettings::read(params);
  const std::unique_ptr<Device> device = createDevice();
  device->setRobot(robot);
  device->configure(params);
}

DeviceNodeletBase::~DeviceNodeletBase() {
  {
    std::lock_guard lk(pace_mutex_);
    shutting_down_ = true;  // no more woken refreshes are posted
  }
  gather_timer_.stop();
  refresh_timer_.stop();
  if (reporter_) reporter_->stop();
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
    const robot_core::Params params = robot_core::Params::of(pnh);
    const DeviceSettings settings = DeviceSettings::read(params);
    DeviceContext ctx{getNodeHandle(), pnh, getName(), settings.rate};
    rate_ = settings.rate;
    max_rate_ = settings.max_rate;
    const double diagnostic_period = settings.diagnostic_period;
    startup_grace_ = settings.startup_grace;
    required_ = settings.required;
    started_ = ros::Time::now();

    pacer_ = robot_core::LoopPacer(1.0 / rate_, 1.0 / max_rate_);
    device_ = createDevice();
    device_->setWakeHandler([this](const ros::Time& stamp) { wake(stamp); });
    device_->setRobot(robot_core::RobotGeometry::fromParameterServer());
    device_->configure(params);
    device_->init(ctx);
    effector_ = dynamic_cast<Effector*>(device_.get());

    reporter_ = std::make_unique<robot_core::DiagnosticReporter>(
        getNodeHandle(), getName(), "device", getName(), diagnostic_period,
        [this](diagnostic_updater::DiagnosticStatusWrapper& stat) { diagnose(stat); });
    if (effector_)
      deactivated_sub_ = getNodeHandle().subscribe("/effectors/deactivated", 1, &DeviceNodeletBase::onDeactivated, this);
    refresh_timer_ = getNodeHandle().createTimer(ros::Duration(1.0 / rate_), &DeviceNodeletBase::onTimer, this);
    // The readings of one board exchange arrive on separate topics, a fraction of a millisecond
    // apart: a woken refresh waits for kGatherQuiet without a new one (at most kGatherLimit
    // after the first), so it takes them all in one run and one token of the pacer.
    gather_timer_ = getNodeHandle().createTimer(ros::Duration(kGatherQuiet), &DeviceNodeletBase::onGathered, this,
                                                    true /* one-shot */, false /* started by wake() */);
    initialized_ = true;  // from now on an arriving input may run refresh()
    NODELET_INFO("device %s refreshing at %.1f Hz (woken up to %.1f Hz)%s", getName().c_str(), rate_, max_rate_,
                 effector_ ? " (effector)" : "");
  } catch (const robot_core::ParameterError& e) {
    NODELET_FATAL("%s", e.what());
    throw;
  } catch (const std::exception& e) {
    NODELET_FATAL("device %s failed to start: %s", getName().c_str(), e.what());
    throw;
  }
}

void DeviceNodeletBase::wake(const ros::Time& stamp) {
  double delay = kGatherQuiet;
  {
    std::lock_guard lk(pace_mutex_);
    if (!initialized_ || shutting_down_) return;
    const ros::Time now = ros::Time::now();
    if (wake_posted_) {
      // Still gathering: the refresh waits for a quiet moment after the burst, up to its limit.
      // (A wake deferred to the rate limit already waits for its token.)
      if (!gathering_ || (now - gather_started_).toSec() >= kGatherLimit) return;
    } else {
      // The other readings of an exchange that was already refreshed do not wake it again: one
      // board exchange costs one run of the rate limit, however its topics were delayed. (A
      // message without a stamp, a velocity command, always wakes: under a simulated clock two
      // of them often arrive at the same ROS time.)
      if (!stamp.isZero()) {
        if (stamp <= newest_woken_stamp_) return;
        newest_woken_stamp_ = stamp;
      }
      pacer_.wake();
      const double wait = pacer_.next() - now.toSec();  // > 0: no token yet
      wake_posted_ = true;
      gather_started_ = now;
      gathering_ = wait <= 0.0;
      if (!gathering_) {
        ++wakes_deferred_;
        delay = std::max(kGatherQuiet, wait);
      }
    }
  }
  restartGatherTimer(delay);
}

// A new one-shot each time: re-arming a one-shot from inside its own callback is undone when
// the callback returns.
void DeviceNodeletBase::restartGatherTimer(double delay) {
  gather_timer_.stop();
  gather_timer_.setPeriod(ros::Duration(delay));
  gather_timer_.start();
}

void DeviceNodeletBase::onGathered(const ros::TimerEvent&) {
  {
    std::lock_guard lk(pace_mutex_);
    if (!pacer_.woken()) {  // a tick has refreshed meanwhile
      wake_posted_ = false;
      return;
    }
    const double wait = pacer_.next() - ros::Time::now().toSec();
    if (wait > 0.0) {  // the token is not there yet: wait on for it
      gathering_ = false;
      restartGatherTimer(std::max(kGatherQuiet, wait));
      return;
    }
    wake_posted_ = false;
    ++woken_refreshes_;
  }
  refreshIfDue(false);
}

void DeviceNodeletBase::onTimer(const ros::TimerEvent&) { refreshIfDue(true); }

void DeviceNodeletBase::refreshIfDue(bool tick) {
  // A worker thread that refreshes a device runs in real time from then on (the HAL's
  // ~realtime_priority, robot_core/realtime.h): the inputs and timers it serves are the device
  // loops. Refused, the process WARNs once and its loops run at normal priority.
  thread_local bool realtime_entered = false;
  if (!realtime_entered) {
    realtime_entered = true;
    robot_core::enterRealtime("a device loop");
  }
  const double now = ros::Time::now().toSec();  // the rate meter, like the pacer, counts ROS time
  {
    std::lock_guard lk(pace_mutex_);
    if (!(tick ? pacer_.dueForTick(now) : pacer_.due(now))) return;
    pacer_.ran(now);
  }
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
  std::lock_guard lk(stats_mutex_);
  meter_.tick(now, busy);
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
    std::lock_guard lk(stats_mutex_);
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
    stat.addf("max rate [Hz]", "%.2f", max_rate_);
    stat.addf("achieved rate [Hz]", "%.2f", achieved);
    stat.addf("mean refresh time [ms]", "%.3f", 1e3 * meter_.meanBusy());
    stat.add("refresh errors", refresh_errors_);
    stat.add("last error", last_error_);
  }
  {
    std::lock_guard lk(pace_mutex_);
    stat.add("woken refreshes", woken_refreshes_);                  // run at once for an arriving input
    stat.add("wakes deferred to the rate limit", wakes_deferred_);  // inputs faster than ~max_rate
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
