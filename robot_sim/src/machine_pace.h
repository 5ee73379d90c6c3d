// The real-time factor of "as fast as the machine goes" (~real_time_factor 0): the simulator
// must not run ahead of the robot it simulates. A world stepping flat out takes a whole core and
// starves the boards' drivers, HAL and the brain, which then miss their rates and reply windows
// (at factor 0 without this: every board STALE, the robot never ready). So the simulator paces
// at the factor that keeps the machine just short of saturation: once a second it reads the
// machine's busy share from /proc/stat and raises the factor by 15 % below `low`, lowers it by
// 15 % above `high`.
#pragma once

#include <algorithm>
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
  bool update() {
    unsigned long long busy = 0, total = 0;
    if (!sample(busy, total) || total <= total_) return false;
    last_busy_ = static_cast<double>(busy - busy_) / static_cast<double>(total - total_);
    busy_ = busy;
    total_ = total;
    const double before = factor_;
    if (last_busy_ > high_) factor_ = std::max(min_, factor_ * 0.85);
    else if (last_busy_ < low_) factor_ = std::min(max_, factor_ * 1.15);
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

}  // namespace robot_sim
