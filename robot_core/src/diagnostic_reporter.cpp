#include "robot_core/diagnostic_reporter.h"

#include <diagnostic_msgs/DiagnosticArray.h>

namespace robot_core {

DiagnosticReporter::DiagnosticReporter(ros::NodeHandle nh, const std::string& node_name, const std::string& task,
                                       const std::string& hardware_id, double period, Evaluate evaluate)
    : name_((!node_name.empty() && node_name[0] == '/' ? node_name.substr(1) : node_name) + ": " + task),
      hardware_id_(hardware_id),
      period_(period),
      evaluate_(std::move(evaluate)) {
  pub_ = nh.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
  timer_ = nh.createTimer(ros::Duration(kCheckPeriod), [this](const ros::TimerEvent&) { check(); });
}

DiagnosticReporter::~DiagnosticReporter() { stop(); }

void DiagnosticReporter::stop() { timer_.stop(); }  // waits for a check that is running

void DiagnosticReporter::check() {
  std::lock_guard<std::mutex> lk(mutex_);
  diagnostic_updater::DiagnosticStatusWrapper status;
  status.name = name_;
  status.hardware_id = hardware_id_;
  status.level = diagnostic_msgs::DiagnosticStatus::ERROR;
  status.message = "No message was set";
  evaluate_(status);
  const ros::Time now = ros::Time::now();
  // (A clock that went back, a simulation restarted, does not hold the report for long.)
  const bool went_back = now < last_published_;
  const bool due = now >= next_ || went_back;
  if (status.level == published_level_ && !due) return;
  // A level that flaps (a rate hovering at its WARN threshold) is said at most every kMinInterval.
  if (!due && (now - last_published_).toSec() < kMinInterval) return;
  published_level_ = status.level;
  last_published_ = now;
  next_ = now + ros::Duration(period_);
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = now;
  array.status.push_back(status);
  pub_.publish(array);
}

}  // namespace robot_core
