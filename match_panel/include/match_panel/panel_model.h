// What the match panel shows and does, without Qt: the subscriptions, the service calls and a
// snapshot of everything to display. The rviz widget (match_panel.cpp) only renders snapshots
// and forwards clicks; the rostest drives this class directly.
#pragma once

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <robot_sim/MatchState.h>
#include <smart_brain/MatchStatus.h>
#include <smart_brain/SmachContainerStatus.h>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "match_panel/active_path.h"
#include "match_panel/diagnostics_summary.h"

namespace match_panel {

// What a button did: ok, and the service's answer or why there was none.
struct ServiceResult {
  bool ok = false;
  std::string message;
};

// Everything the panel displays at one instant, formatted where that is the display's job.
struct Snapshot {
  std::string robot_name;      // /robot/name, "unknown" without it
  bool have_status = false;    // a /brain/match_status arrived
  std::string state;           // waiting_for_start, running, ended, untimed ("" before any status)
  std::string strategy;        // running strategy ("" before any status)
  bool ready = false;
  std::string readiness;
  double remaining = 0.0;      // [s] counted down since the last status while running
  std::string clock;           // "1:23.4", or "—" with no status or no match timer
  bool have_score = false;     // /sim/match seen (simulation only)
  int score_ours = 0;
  int score_opponent = 0;
  std::string score;           // "12 : 4" ("final" appended once over), or "—"
  std::string active_path;     // "/MATCH_2009/BODY/..." or ""
  std::string last_trigger;    // the last trigger fired, or ""
  std::vector<DeviceLine> devices;  // worst first
  std::vector<std::string> strategies;  // what /brain/switch_strategy last listed
};

class PanelModel {
 public:
  // Topics and services are absolute (the brain, HAL and simulator run in the root namespace).
  // Callbacks run on a thread of the model's own, never on the caller's (rviz's GUI) thread.
  PanelModel();
  ~PanelModel();
  PanelModel(const PanelModel&) = delete;
  PanelModel& operator=(const PanelModel&) = delete;

  Snapshot snapshot(const ros::Time& now) const;

  // Service calls: blocking, each waits at most `wait` for its service to appear. The widget
  // runs them off the GUI thread.
  // In simulation (/sim/set_switch exists) pulls the simulated start cord, else calls /brain/start.
  ServiceResult startMatch(const ros::Duration& wait = ros::Duration(1.0));
  // Asks /brain/switch_strategy to run `name`; the answer's strategy list is kept.
  ServiceResult switchStrategy(const std::string& name, const ros::Duration& wait = ros::Duration(1.0));
  // Fetches the strategy list: a switch to the empty name, which the brain refuses (it would
  // restart the strategy for its current name) and answers with every registered strategy.
  ServiceResult refreshStrategies(const ros::Duration& wait = ros::Duration(1.0));
  // /effectors/deactivate: every effector stops until reactivated.
  ServiceResult emergencyStop(const ros::Duration& wait = ros::Duration(1.0));

 private:
  void onMatchStatus(const smart_brain::MatchStatus::ConstPtr& msg);
  void onMatch(const robot_sim::MatchState::ConstPtr& msg);
  void onContainerStatus(const smart_brain::SmachContainerStatus::ConstPtr& msg);
  void onDiagnostics(const diagnostic_msgs::DiagnosticArray::ConstPtr& msg);

  ros::CallbackQueue queue_;
  ros::NodeHandle nh_;
  std::unique_ptr<ros::AsyncSpinner> spinner_;
  std::vector<ros::Subscriber> subs_;
  std::string robot_name_;

  mutable std::mutex mutex_;  // guards what follows: written by the callbacks, read by snapshot()
  smart_brain::MatchStatus::ConstPtr status_;
  ros::Time status_time_;     // when the status was true: its stamp, else its receipt
  robot_sim::MatchState::ConstPtr match_;
  ActivePath active_;
  DiagnosticsSummary diagnostics_;
  std::vector<std::string> strategies_;
};

}  // namespace match_panel
