// Loop groups: boards naming the same ~loop are serviced in turn by one thread (the
// original Scheduler), so boards on one I2C bus never contend. A board without a loop gets a
// thread of its own. Each member is serviced when its own period is due, or sooner when woken
// by a command (paced so its rate stays a ceiling: robot_core/loop_pacer.h). Time is ROS time,
// so loops follow /clock in simulation.
#pragma once

#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace hcl_drivers {

class LoopScheduler {
 public:
  using Work = std::function<void()>;

  // The process-wide scheduler shared by all boards loaded into one nodelet manager.
  static LoopScheduler& instance();

  LoopScheduler() = default;
  ~LoopScheduler();
  LoopScheduler(const LoopScheduler&) = delete;
  LoopScheduler& operator=(const LoopScheduler&) = delete;

  // Service `work` at `rate_hz` on loop `loop` (empty: a private loop named after `member`).
  void join(const std::string& loop, const std::string& member, double rate_hz, Work work);
  // Service `member` as soon as its rate allows (a command arrived): robot_core/loop_pacer.h.
  void wake(const std::string& member);
  // Stop servicing `member`; returns once its work is not running and never will again.
  void leave(const std::string& member);

  // Names of the members of a loop, in service order (for diagnostics and tests).
  std::vector<std::string> members(const std::string& loop) const;
  std::string loopOf(const std::string& member) const;

 private:
  class Loop;
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Loop>> loops_;
  std::map<std::string, std::string> loop_of_member_;
};

}  // namespace hcl_drivers
