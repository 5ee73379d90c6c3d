#include "match_panel/panel_model.h"

#include <robot_core/params.h>
#include <robot_sim/SetSwitch.h>
#include <smart_brain/SwitchStrategy.h>
#include <std_srvs/Trigger.h>

#include "match_panel/match_clock.h"

namespace match_panel {

namespace {

const char* const kNoValue = "\xe2\x80\x94";  // an em dash: nothing to show

// Calls `name` once it exists (within `wait`); a missing service is a result, not an exception.
template <class Srv>
ServiceResult call(const std::string& name, Srv& srv, const ros::Duration& wait) {
  if (!ros::service::waitForService(name, wait)) return {false, name + " is not available"};
  if (!ros::service::call(name, srv)) return {false, name + " failed (the node went away?)"};
  return {true, ""};
}

}  // namespace

PanelModel::PanelModel() {
  nh_.setCallbackQueue(&queue_);
  // Latched status and diagnostics arrive however late the panel starts.
  subs_.push_back(nh_.subscribe("/brain/match_status", 1, &PanelModel::onMatchStatus, this));
  subs_.push_back(nh_.subscribe("/sim/match", 1, &PanelModel::onMatch, this));
  // Every container publishes on one topic: a deep queue, so a burst of transitions is not lost.
  subs_.push_back(nh_.subscribe("/brain/smach/container_status", 100, &PanelModel::onContainerStatus, this));
  subs_.push_back(nh_.subscribe("/diagnostics", 50, &PanelModel::onDiagnostics, this));
  // config/<robot>.yaml robot/name; read once: it does not change while the robot runs. The panel
  // shows what it can: a description without a usable name is "unknown", not a broken panel.
  try {
    robot_name_ = robot_core::Params::of(ros::NodeHandle("/robot")).optionalString("name", "");
  } catch (const std::exception& e) {
    ROS_WARN("match panel: %s", e.what());
  }
  if (robot_name_.empty()) robot_name_ = "unknown";
  spinner_.reset(new ros::AsyncSpinner(1, &queue_));
  spinner_->start();
}

PanelModel::~PanelModel() {
  spinner_->stop();
  for (auto& s : subs_) s.shutdown();
}

void PanelModel::onMatchStatus(const smart_brain::MatchStatus::ConstPtr& msg) {
  const ros::Time now = ros::Time::now();
  std::lock_guard<std::mutex> lock(mutex_);
  status_ = msg;
  // The stamp says when `remaining` was true (a latched message can be old); a stamp from the
  // future or none (unstamped) falls back to the receipt time.
  status_time_ = (!msg->header.stamp.isZero() && msg->header.stamp <= now) ? msg->header.stamp : now;
}

void PanelModel::onMatch(const robot_sim::MatchState::ConstPtr& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  match_ = msg;
}

void PanelModel::onContainerStatus(const smart_brain::SmachContainerStatus::ConstPtr& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  active_.update(msg->path, msg->initial_states, msg->active_states);
}

void PanelModel::onDiagnostics(const diagnostic_msgs::DiagnosticArray::ConstPtr& msg) {
  const ros::Time now = ros::Time::now();
  std::lock_guard<std::mutex> lock(mutex_);
  diagnostics_.update(*msg, now);
}

Snapshot PanelModel::snapshot(const ros::Time& now) const {
  std::lock_guard<std::mutex> lock(mutex_);
  Snapshot s;
  s.robot_name = robot_name_;
  s.clock = kNoValue;
  s.score = kNoValue;
  if (status_) {
    s.have_status = true;
    s.state = status_->state;
    s.strategy = status_->strategy;
    s.ready = status_->ready;
    s.readiness = status_->readiness;
    if (s.state != "untimed") {
      s.remaining = countDown(status_->remaining, (now - status_time_).toSec(), s.state == "running");
      s.clock = formatClock(s.remaining);
    }
    const std::string root = active_.currentRoot(s.strategy);
    s.active_path = active_.path(root);
    s.last_trigger = active_.lastTrigger(root);
  }
  if (match_) {
    s.have_score = true;
    s.score_ours = match_->score_ours;
    s.score_opponent = match_->score_opponent;
    s.score = std::to_string(s.score_ours) + " : " + std::to_string(s.score_opponent) + (match_->over ? " final" : "");
  }
  s.devices = diagnostics_.lines(now);
  s.strategies = strategies_;
  return s;
}

ServiceResult PanelModel::startMatch(const ros::Duration& wait) {
  // The simulator's switch exists only in simulation: there the cord is pulled as a person
  // would (the whole chain, emulator to brain, sees it); on the robot the brain is told.
  if (ros::service::exists("/sim/set_switch", false)) {
    robot_sim::SetSwitch srv;
    srv.request.name = "start_cord";
    srv.request.closed = false;
    ServiceResult r = call("/sim/set_switch", srv, wait);
    if (!r.ok) return r;
    return {srv.response.ok != 0, srv.response.ok ? "start cord pulled (simulation)" : srv.response.message};
  }
  std_srvs::Trigger srv;
  ServiceResult r = call("/brain/start", srv, wait);
  if (!r.ok) return r;
  return {srv.response.success != 0, srv.response.message.empty() ? "/brain/start called" : srv.response.message};
}

ServiceResult PanelModel::switchStrategy(const std::string& name, const ros::Duration& wait) {
  smart_brain::SwitchStrategy srv;
  srv.request.name = name;
  ServiceResult r = call("/brain/switch_strategy", srv, wait);
  if (!r.ok) return r;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    strategies_ = srv.response.available;
  }
  return {srv.response.success != 0, srv.response.message};
}

ServiceResult PanelModel::refreshStrategies(const ros::Duration& wait) {
  smart_brain::SwitchStrategy srv;  // name "": refused, nothing switched
  ServiceResult r = call("/brain/switch_strategy", srv, wait);
  if (!r.ok) return r;
  std::lock_guard<std::mutex> lock(mutex_);
  strategies_ = srv.response.available;
  return {true, std::to_string(strategies_.size()) + " strategies"};
}

ServiceResult PanelModel::emergencyStop(const ros::Duration& wait) {
  std_srvs::Trigger srv;
  ServiceResult r = call("/effectors/deactivate", srv, wait);
  if (!r.ok) return r;
  return {srv.response.success != 0, srv.response.message};
}

}  // namespace match_panel
