// The nodelet that hosts one Board: reads the common parameters, registers the board with
// its loop, measures it and reports it on /diagnostics. Board authors never touch this;
// they export their board with HCL_EXPORT_BOARD (bottom of this file).
//
// Common parameters (private namespace of the board):
//   ~rate             [Hz] polling rate, required, > 0
//   ~loop             loop group name; boards naming the same loop share one thread (optional)
//   ~stale_timeout    [s] no good exchange for this long = STALE (default max(0.3, 3 / rate))
//   ~diagnostic_period [s] how often /diagnostics is published (default 0.25)
#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include <atomic>
#include <memory>
#include <mutex>
#include <string>

#include "hcl_drivers/board.h"
#include "hcl_drivers/rate_meter.h"

namespace hcl_drivers {

class BoardNodeletBase : public nodelet::Nodelet {
 public:
  ~BoardNodeletBase() override;

 protected:
  virtual std::unique_ptr<Board> createBoard() const = 0;

 private:
  void onInit() final;
  void serviceOnce();
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);

  std::unique_ptr<Board> board_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::Timer diagnostic_timer_;  // ROS time: reports follow the simulated clock
  std::string member_name_;
  bool joined_ = false;

  double rate_ = 0.0;
  double stale_timeout_ = 0.0;

  mutable std::mutex stats_mutex_;  // guards everything below (loop thread vs diagnostics)
  RateMeter meter_;
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

// Export a board type as a nodelet plugin; add a matching entry to nodelet_plugins.xml with
// name="hcl_drivers/<BoardName>" type="hcl_drivers::<BoardName>Nodelet".
#define HCL_EXPORT_BOARD(BoardName)                                                      \
  namespace hcl_drivers {                                                                \
  using BoardName##Nodelet = BoardNodelet<BoardName>;                                    \
  }                                                                                      \
  PLUGINLIB_EXPORT_CLASS(hcl_drivers::BoardName##Nodelet, nodelet::Nodelet)
