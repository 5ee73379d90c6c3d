// The Board: what every HCL driver implements. One instance per physical circuit board.
//
// A board mirrors its firmware's variables and never interprets them (that is HAL's job).
// The framework (BoardNodelet) calls:
//   configure(params)  first: read every ~parameter into members (robot_core/params.h) and
//               throw ParameterError for a bad one: the node stops with that one line. Nothing
//               else: check_config runs it over a config file, with no master and no bus, and
//               calls every key it never asked for unknown. So the object itself is built there
//               too, with no ros::init: no ros::NodeHandle (or anything holding one) as a member
//               constructed with the board; make those in init().
//   init(ctx)   once, at load, after configure(): open the bus, advertise ~state, subscribe
//               commands, with the values configure() read.
//   service()   at the configured ~rate on a polling thread (never the nodelet callback queue):
//               send pending commands, read the variables, publish the latched state.
//               Return true when the board answered; on failure call fail("why") and return false.
//   halt()      on shutdown and whenever commands went stale: put the board in a safe state.
//   check(ctx, report)  the hardware doctor only (`rosrun hcl_drivers doctor`), after configure()
//               instead of init(): open the channel and probe the board (identity,
//               firmware version, answers) without configuring, starting or driving anything;
//               one row per finding into `report` (board_check.h). Never throws for a board that
//               does not answer: that is a FAIL row with a hint.
// Command callbacks run on the nodelet callback queue, concurrently with service(): guard
// shared state with a mutex.
#pragma once

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <ros/ros.h>

#include <functional>
#include <string>

#include <robot_core/params.h>

#include "hcl_drivers/board_check.h"

namespace hcl_drivers {

// Everything a board needs from its host at init().
struct BoardContext {
  ros::NodeHandle nh;   // the manager's namespace (global topics)
  ros::NodeHandle pnh;  // the board's private namespace: ~rate, ~state, ...
  std::string name;     // the board's node name, e.g. "/hcl/example_board"
  double rate = 0.0;    // configured polling rate [Hz], already validated
  std::function<void()> wake;  // service the board as soon as its rate allows (subscribeCommand calls it)
};

class Board {
 public:
  virtual ~Board() = default;

  virtual void configure(const robot_core::Params& params) = 0;
  virtual void init(BoardContext& ctx) = 0;
  virtual bool service() = 0;
  virtual void halt() = 0;

  // Board-specific diagnostic values (firmware version, bus counters, ...). Optional.
  virtual void diagnose(diagnostic_updater::DiagnosticStatusWrapper& /*stat*/) {}

  // The hardware doctor's probe (see above). Default: one WARN row saying the type has none.
  virtual void check(BoardContext& ctx, CheckReport& report);

  // Read by the framework after service() returned false.
  const std::string& lastError() const { return last_error_; }

 protected:
  // Record why the last exchange failed (shown on /diagnostics, counted by the framework).
  void fail(const std::string& reason) { last_error_ = reason; }

 private:
  std::string last_error_;
};

// A command topic of a board (~motor/<name>/command, ...) in its private namespace: the newest
// command only (queue 1), sent without Nagle's delay (with Nagle a command waits for the
// acknowledgement of the previous one, which the receiver may delay by up to 40 ms). After the
// callback the board's loop is woken, so the command goes out on the bus at once rather than at
// the next period (within the board's rate: robot_core/loop_pacer.h).
template <class M>
ros::Subscriber subscribeCommand(BoardContext& ctx, const std::string& topic,
                                 const boost::function<void(const typename M::ConstPtr&)>& callback) {
  const std::function<void()> wake = ctx.wake;
  return ctx.pnh.subscribe<M>(topic, 1, [callback, wake](const typename M::ConstPtr& m) {
    callback(m);
    if (wake) wake();
  }, ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
}

}  // namespace hcl_drivers
