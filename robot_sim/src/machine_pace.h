// The real-time factor of "as fast as the machine goes" (~real_time_factor 0): the simulator
// must not run ahead of the robot it simulates. A world stepping flat out takes a whole core and
// starves the boards' drivers, HAL and the brain, which then miss their rates and reply windows
// (every board goes STALE and the robot is never ready). So the simulator paces
// at the factor that keeps the machine just short of saturation: once a second it reads the
// machine's busy share from /proc/stat and lowers the factor by 15 % above `high`; below `low`
// it raises it by 15 %, or in proportion to the idle share when the machine is far from busy (at
// most 1.5x a second), so a short test does not spend its first seconds creeping up from 1.0.
// The robot's cost grows slower than the factor (part of it is per wall second), so the
// proportional step undershoots rather than overshoots.
//
// A busy share under the band does not prove the robot keeps up: a loop that waits on round
// trips (a shared CAN loop polling several boards, each request/answer exchange through the
// emulated bus) falls behind with the CPU half idle. So the pace also watches the robot's work
// rate, the driver requests the emulators answered per simulated second (RobotKeepingUp): the factor
// rises only while that rate holds (95 % of the best recent rate), and comes down by 15 % a
// second while it is under 90 %, but not below real time on that account: at factor 1 the
// robot runs as on the table, whatever its boards do (a board silenced by a fault polls less).
#pragma once

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

namespace robot_sim {

class MachinePace {
 public:
  MachinePace(double start = 1.0, double low = 0.80, double high = 0.90, double min = 0.25, double max = 50.0)
      : factor_(start), low_(low), high_(high), min_(min), max_(max) {
    sample(busy_, total_);
  }

  double factor() const { return factor_; }
  double lastBusy() const { return last_busy_; }

  // Called about once a second: true when the factor changed.
  bool update(bool robot_lagging = false, bool may_rise = true) {
    unsigned long long busy = 0, total = 0;
    if (!sample(busy, total) || total <= total_) return false;
    const double share = static_cast<double>(busy - busy_) / static_cast<double>(total - total_);
    busy_ = busy;
    total_ = total;
    return adjust(share, robot_lagging, may_rise);
  }

  // One step of the controller for a measured busy share in [0, 1], whether the robot kept up
  // and whether it may go faster yet: true when the factor changed.
  bool adjust(double busy_share, bool robot_lagging = false, bool may_rise = true) {
    last_busy_ = busy_share;
    const double before = factor_;
    if (last_busy_ > high_) factor_ = std::max(min_, factor_ * 0.85);
    else if (robot_lagging) factor_ = std::max(std::min(factor_, 1.0), factor_ * 0.85);
    else if (last_busy_ < low_ && may_rise) {
      const double toward_target = 0.5 * (low_ + high_) / std::max(last_busy_, 0.01);
      factor_ = std::min(max_, factor_ * std::min(1.5, std::max(1.15, toward_target)));
    }
    return factor_ != before;
  }

 private:
  // Jiffies busy and in total over all cores since boot (the first line of /proc/stat).
  static bool sample(unsigned long long& busy, unsigned long long& total) {
    std::ifstream in("/proc/stat");
    std::string cpu;
    unsigned long long v[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    if (!(in >> cpu) || cpu != "cpu") return false;
    for (auto& x : v) in >> x;
    total = 0;
    for (auto x : v) total += x;
    busy = total - v[3] - v[4];  // minus idle and iowait
    return true;
  }

  double factor_, low_, high_, min_, max_;
  unsigned long long busy_ = 0, total_ = 0;
  double last_busy_ = 0.0;
};

// Whether the robot's boards keep their request rate in simulated time. Fed once a second with
// the emulators' total answered requests and the simulated time. The rate is settled once two
// seconds in a row agree within 5 % (the boards are up and polling): the factor rises only then,
// so the reference is a rate the robot reached at the starting pace. The reference is the best
// rate seen, decaying by 1 % a second so a burst or a lasting change (a board halted) does not
// set it for good.
class RobotKeepingUp {
 public:
  explicit RobotKeepingUp(double lag_below = 0.90, double rise_above = 0.95, double decay = 0.99)
      : lag_below_(lag_below), rise_above_(rise_above), decay_(decay) {}

  // True when the rate since the last call is under lag_below of the reference.
  bool lagging(unsigned long polls, double sim_time) {
    bool lag = false;
    if (have_last_ && sim_time > last_sim_ + 1e-6 && polls >= last_polls_) {
      const double rate = static_cast<double>(polls - last_polls_) / (sim_time - last_sim_);
      if (rate > 0.0 && std::abs(rate - rate_) <= 0.05 * std::max(rate, rate_)) settled_ = true;
      rate_ = rate;
      reference_ = std::max(reference_ * decay_, rate_);
      lag = rate_ < lag_below_ * reference_;
    }
    have_last_ = true;
    last_polls_ = polls;
    last_sim_ = sim_time;
    return lag;
  }
  bool settled() const { return settled_; }
  // Settled and at the reference's pace: the factor may go up.
  bool mayRise() const { return settled_ && rate_ >= rise_above_ * reference_; }
  double rate() const { return rate_; }
  double reference() const { return reference_; }

 private:
  double lag_below_, rise_above_, decay_;
  bool have_last_ = false, settled_ = false;
  unsigned long last_polls_ = 0;
  double last_sim_ = 0.0, rate_ = 0.0, reference_ = 0.0;
};

}  // namespace robot_sim
