// One component's /diagnostics status on diagnostic_updater's convention: about once a period
// (the component's ~diagnostic_period, 1 s by default) and at once when its level changes.
//
// The status is evaluated every kCheckPeriod of ROS time, so a change of level reaches
// /diagnostics within that (a level that flaps, at most every kMinInterval); between changes
// only one status a period is sent. A change of message alone waits for the period. Because the
// evaluation runs many times per published report, it must only read: a transient a component
// wants seen (a reset, a bus-off it recovered from) is held for a while where it is counted, not
// "since the last report".
#pragma once

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <ros/ros.h>

#include <functional>
#include <mutex>
#include <string>

namespace robot_core {

class DiagnosticReporter {
 public:
  using Evaluate = std::function<void(diagnostic_updater::DiagnosticStatusWrapper&)>;
  static constexpr double kCheckPeriod = 0.05;  // [s, ROS time] a level change is published within this
  static constexpr double kMinInterval = 0.1;   // [s, ROS time] between two reports of changes

  // Publishes on /diagnostics (nh's graph) a status named "<node name>: <task>" (the node name
  // without its leading slash, as diagnostic_updater names it) with `hardware_id`.
  DiagnosticReporter(ros::NodeHandle nh, const std::string& node_name, const std::string& task,
                     const std::string& hardware_id, double period, Evaluate evaluate);
  ~DiagnosticReporter();
  DiagnosticReporter(const DiagnosticReporter&) = delete;
  DiagnosticReporter& operator=(const DiagnosticReporter&) = delete;

  // Stops the checks, waiting for one that is running (before what `evaluate` reads is destroyed).
  void stop();

 private:
  void check();

  const std::string name_, hardware_id_;
  const double period_;
  const Evaluate evaluate_;
  ros::Publisher pub_;
  ros::Timer timer_;
  std::mutex mutex_;             // one check at a time (the callback queue may be multi-threaded)
  int published_level_ = -1;     // none yet
  ros::Time last_published_;
  ros::Time next_;               // the periodic report is due from then
};

}  // namespace robot_core
