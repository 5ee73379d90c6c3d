// The nodelet that hosts one Board: reads the common parameters, registers the board with
// its loop, measures it and reports it on /diagnostics. Board authors never touch this;
// they export their board with HCL_EXPORT_BOARD (bottom of this file).
//
// Common parameters (private namespace of the board, ~rate, ~loop, ~required, ...): read and
// described in BoardSettings::read() (the table: hcl_drivers/PARAMETERS.md, make docs).
// A change of diagnostic level is published at once (robot_core/diagnostic_reporter.h); fewer
// failed exchanges in a row than ~failures_for_error are a WARN: one late answer on a busy bus
// is not a fault. ~required is published as the `required` value of the board's /diagnostics
// status. A board whose channel cannot be opened is STALE and retried every ~reopen_period; the
// node and its other boards keep running.
#pragma once

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include <atomic>
#include <memory>
#include <mutex>
#include <string>

#include "hcl_drivers/board.h"
#include <robot_core/configurable_component.h>
#include <robot_core/diagnostic_reporter.h>
#include <robot_core/priority_inheritance_mutex.h>
#include <robot_core/rate_meter.h>

namespace hcl_drivers {

// The common parameters, read by the framework for every board.
struct BoardSettings {
  double rate = 0.0;
  double stale_timeout = 0.0;
  double reopen_period = 1.0;
  bool required = true;
  std::string loop;
  double diagnostic_period = 1.0;
  unsigned long failures_for_error = 3;

  static BoardSettings read(const robot_core::Params& params);
};

class BoardNodeletBase : public nodelet::Nodelet, public robot_core::ConfigurableComponent {
 public:
  ~BoardNodeletBase() override;
  // A fresh board of this plugin's type, not configured: the hardware doctor calls its
  // configure() and check().
  std::unique_ptr<Board> newBoard() const { return createBoard(); }
  // The common parameters and the board's own, over `params` (check_config, with no master).
  void readConfig(const robot_core::Params& params, const robot_core::RobotGeometry& robot) const override;

 protected:
  virtual std::unique_ptr<Board> createBoard() const = 0;

 private:
  void onInit() final;
  // Create the board and init() it (open its channel); on failure keep reporting STALE and retry.
  void tryOpen();
  void serviceOnce();
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);
  // The framework's part of the status (stats_mutex_ held); the board to add its own, if open.
  Board* diagnoseFramework(diagnostic_updater::DiagnosticStatusWrapper& stat);

  robot_core::Params params_;     // the board's private namespace, fetched once at load
  std::unique_ptr<Board> board_;  // null until its channel opened
  std::unique_ptr<robot_core::DiagnosticReporter> reporter_;  // checks on ROS time: the simulated clock
  ros::Timer reopen_timer_;      // ROS time, like the polling: the retries follow the simulated clock
  std::mutex open_mutex_;        // one tryOpen() at a time (the callback queue is multi-threaded)
  std::string member_name_;
  bool joined_ = false;
  BoardSettings settings_;
  std::string open_error_;  // why the channel could not be opened (empty once open)
  std::string joined_loop_;  // the loop the board polls on, once open
  unsigned long open_attempts_ = 0;

  // Guards everything below: the real-time loop thread vs the diagnostics' checks (normal
  // priority), with priority inheritance so the loop never waits behind a preempted check.
  mutable robot_core::PriorityInheritanceMutex stats_mutex_;
  robot_core::RateMeter meter_;
  ros::Time started_;
  ros::Time last_good_;
  unsigned long exchanges_ = 0;
  unsigned long errors_ = 0;
  unsigned long consecutive_errors_ = 0;
  std::string last_error_;
  bool halted_for_staleness_ = false;
};

template <class BoardT>
class BoardNodelet : public BoardNodeletBase {
 protected:
  std::unique_ptr<Board> createBoard() const override { return std::make_unique<BoardT>(); }
};

}  // namespace hcl_drivers

// Export a board as nodelet plugin "hcl_drivers/<BoardName>", the `type` of its config block:
//   HCL_EXPORT_BOARD(MyBoard, "one line for `rosrun nodelet declared_nodelets`");
// at the start of a line, the description without double quotes. The build writes
// nodelet_plugins.xml from these lines (cmake/generate_plugin_xml.cmake): nothing to register.
#define HCL_EXPORT_BOARD(BoardName, Description)                                        \
  namespace hcl_drivers {                                                               \
  using BoardName##Nodelet = BoardNodelet<BoardName>;                                   \
  }                                                                                     \
  PLUGINLIB_EXPORT_CLASS(hcl_drivers::BoardName##Nodelet, nodelet::Nodelet)
