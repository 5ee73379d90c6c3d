#include "hcl_drivers/board_nodelet.h"

#include <diagnostic_msgs/DiagnosticStatus.h>

#include <algorithm>
#include <chrono>

#include "hcl_drivers/loop_scheduler.h"
#include <robot_core/params.h>

namespace hcl_drivers {

using robot_core::ParameterError;

using diagnostic_msgs::DiagnosticStatus;

BoardNodeletBase::~BoardNodeletBase() {
  reopen_timer_.stop();
  if (reporter_) reporter_->stop();
  if (joined_) LoopScheduler::instance().leave(member_name_);  // no service() runs after this
  if (board_) {
    try {
      board_->halt();
    } catch (const std::exception& e) {
      ROS_ERROR("%s: halt() failed on shutdown: %s", member_name_.c_str(), e.what());
    }
  }
}

BoardSettings BoardSettings::read(const robot_core::Params& p) {
  BoardSettings s;
  p.describe("rate", "[Hz] polling rate of the board");
  s.rate = p.requireDouble("rate");
  p.requirePositive("rate", s.rate);
  p.describe("stale_timeout", "[s] no good exchange for this long = STALE; when absent max(0.3, 3 / rate)");
  s.stale_timeout = p.optionalDouble("stale_timeout", std::max(0.3, 3.0 / s.rate));
  p.requirePositive("stale_timeout", s.stale_timeout);
  p.describe("reopen_period",
             "[s] a board whose channel cannot be opened (no device, no CAN interface) is STALE, retried this often");
  s.reopen_period = p.optionalDouble("reopen_period", 1.0);
  p.requirePositive("reopen_period", s.reopen_period);
  p.describe("required", "true: the robot is not ready for a match without this board; false: reported, not waited for");
  s.required = p.optionalBool("required", true);
  p.describe("loop", "loop group name; boards naming the same loop share one thread");
  s.loop = p.optionalString("loop", "");
  p.describe("diagnostic_period", "[s] how often /diagnostics is published while the level stays the same");
  s.diagnostic_period = p.optionalDouble("diagnostic_period", 1.0);
  p.requirePositive("diagnostic_period", s.diagnostic_period);
  p.describe("failures_for_error", "failed exchanges in a row that make the board ERROR (fewer are a WARN)");
  const int failures_for_error = p.optionalInt("failures_for_error", 3);
  p.requireInRange("failures_for_error", failures_for_error, 1, 1000);
  s.failures_for_error = static_cast<unsigned long>(failures_for_error);
  return s;
}

void BoardNodeletBase::readConfig(const robot_core::Params& params, const robot_core::RobotGeometry& /*robot*/) const {
  BoardSettings::read(params);
  createBoard()->configure(params);
}

void BoardNodeletBase::onInit() {
  member_name_ = getName();
  params_ = robot_core::Params::of(getPrivateNodeHandle());
  try {
    settings_ = BoardSettings::read(params_);
  } catch (const ParameterError& e) {
    NODELET_FATAL("%s", e.what());
    throw;
  }

  started_ = ros::Time::now();
  // Checked on the callback queue, not the polling thread, so a board stuck in I/O is still reported.
  reporter_ = std::make_unique<robot_core::DiagnosticReporter>(
      getNodeHandle(), getName(), "board", getName(), settings_.diagnostic_period,
      [this](diagnostic_updater::DiagnosticStatusWrapper& stat) { diagnose(stat); });

  tryOpen();  // a bad parameter of the board itself stops the node here, with its one line
  if (!joined_) {
    reopen_timer_ = getNodeHandle().createTimer(ros::Duration(settings_.reopen_period), [this](const ros::TimerEvent&) {
      tryOpen();
      if (joined_) reopen_timer_.stop();
    });
  }
}

void BoardNodeletBase::tryOpen() {
  std::lock_guard<std::mutex> open_lock(open_mutex_);
  if (joined_) return;
  std::unique_ptr<Board> board = createBoard();
  std::string error;
  try {
    BoardContext ctx{getNodeHandle(), getPrivateNodeHandle(), getName(), settings_.rate,
                     [member = member_name_] { LoopScheduler::instance().wake(member); }};
    // read again at each attempt: a value fixed with `rosparam set` while the board is STALE counts
    if (open_attempts_ > 0) params_ = robot_core::Params::of(getPrivateNodeHandle());
    board->configure(params_);
    board->init(ctx);
  } catch (const ParameterError& e) {
    if (open_attempts_ == 0) {
      NODELET_FATAL("%s", e.what());
      throw;
    }
    error = e.what();
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (!error.empty()) {
    std::lock_guard lk(stats_mutex_);
    if (error != open_error_)  // said once per distinct reason, not once a second
      NODELET_ERROR("board %s cannot open its channel: %s; STALE, trying again every %.1f s%s", getName().c_str(),
                    error.c_str(), settings_.reopen_period, settings_.required ? "" : " (optional board)");
    open_error_ = error;
    ++open_attempts_;
    return;
  }
  {
    std::lock_guard lk(stats_mutex_);
    if (open_attempts_ > 0) NODELET_INFO("board %s: channel open after %lu failed attempts", getName().c_str(), open_attempts_);
    open_error_.clear();
    board_ = std::move(board);
  }
  LoopScheduler::instance().join(settings_.loop, member_name_, settings_.rate, [this] { serviceOnce(); });
  joined_ = true;
  {
    std::lock_guard lk(stats_mutex_);
    joined_loop_ = LoopScheduler::instance().loopOf(member_name_);  // said on /diagnostics
  }
  NODELET_INFO("board %s polling at %.1f Hz on loop '%s'", getName().c_str(), settings_.rate, joined_loop_.c_str());
}

void BoardNodeletBase::serviceOnce() {
  const auto wall_start = std::chrono::steady_clock::now();
  const ros::Time start = ros::Time::now();
  bool ok = false;
  std::string error;
  try {
    ok = board_->service();
    if (!ok) error = board_->lastError().empty() ? "board did not answer" : board_->lastError();
  } catch (const std::exception& e) {
    error = std::string("exception in service(): ") + e.what();
  }
  const double busy = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

  bool halt_now = false;
  {
    std::lock_guard lk(stats_mutex_);
    meter_.tick(start.toSec(), busy);
    ++exchanges_;
    if (ok) {
      last_good_ = ros::Time::now();
      consecutive_errors_ = 0;
      halted_for_staleness_ = false;
    } else {
      ++errors_;
      ++consecutive_errors_;
      last_error_ = error;
      const ros::Time since = last_good_.isZero() ? started_ : last_good_;
      if (!halted_for_staleness_ && (ros::Time::now() - since).toSec() > settings_.stale_timeout) {
        halted_for_staleness_ = true;
        halt_now = true;
      }
    }
  }
  if (halt_now) {
    NODELET_ERROR("%s not answering for %.2f s (%s): halting it", getName().c_str(), settings_.stale_timeout, error.c_str());
    try {
      board_->halt();
    } catch (const std::exception& e) {
      NODELET_ERROR("%s: halt() failed: %s", getName().c_str(), e.what());
    }
  }
}

void BoardNodeletBase::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  Board* board = nullptr;
  {
    std::lock_guard lk(stats_mutex_);  // the framework's figures; the board's own after it is released
    board = diagnoseFramework(stat);
  }
  if (board) board->diagnose(stat);  // set once, never reset while the reporter runs
}

Board* BoardNodeletBase::diagnoseFramework(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  const ros::Time now = ros::Time::now();
  const double achieved = meter_.rate();
  const double age = last_good_.isZero() ? -1.0 : (now - last_good_).toSec();
  const double since_start = (now - started_).toSec();

  stat.add("required", settings_.required ? "true" : "false");  // readiness waits only for required boards
  if (!board_) {
    stat.summaryf(DiagnosticStatus::STALE, "cannot open the board's channel: %s (trying again every %.1f s)",
                  open_error_.c_str(), settings_.reopen_period);
    stat.add("open attempts", open_attempts_);
    return nullptr;
  }
  if (last_good_.isZero() && since_start > settings_.stale_timeout) {
    stat.summaryf(DiagnosticStatus::STALE, "no answer from the board since start: %s", last_error_.c_str());
  } else if (age > settings_.stale_timeout) {
    stat.summaryf(DiagnosticStatus::STALE, "board not answering for %.2f s: %s", age, last_error_.c_str());
  } else if (consecutive_errors_ >= settings_.failures_for_error) {
    stat.summaryf(DiagnosticStatus::ERROR, "%lu exchanges in a row failed: %s", consecutive_errors_, last_error_.c_str());
  } else if (consecutive_errors_ > 0) {
    stat.summaryf(DiagnosticStatus::WARN, "last exchange failed (%lu in a row, ERROR from %lu): %s", consecutive_errors_,
                  settings_.failures_for_error, last_error_.c_str());
  } else if (last_good_.isZero()) {
    stat.summary(DiagnosticStatus::WARN, "starting: no answer from the board yet");
  } else if (meter_.count() > 2 && achieved < 0.8 * settings_.rate) {
    stat.summaryf(DiagnosticStatus::WARN, "polling at %.1f Hz, configured %.1f Hz", achieved, settings_.rate);
  } else {
    stat.summary(DiagnosticStatus::OK, "ok");
  }
  stat.add("loop", joined_loop_);
  stat.addf("configured rate [Hz]", "%.2f", settings_.rate);
  stat.addf("achieved rate [Hz]", "%.2f", achieved);
  stat.addf("max period error [ms]", "%.3f", 1e3 * meter_.maxPeriodError(1.0 / settings_.rate));
  stat.addf("mean service time [ms]", "%.3f", 1e3 * meter_.meanBusy());
  stat.addf("max service time [ms]", "%.3f", 1e3 * meter_.maxBusy());
  stat.addf("last good exchange age [s]", "%.3f", age);
  stat.add("exchanges", exchanges_);
  stat.add("errors", errors_);
  stat.add("consecutive errors", consecutive_errors_);
  stat.add("last error", last_error_);
  return board_.get();
}

}  // namespace hcl_drivers
