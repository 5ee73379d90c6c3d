#include "hcl_drivers/loop_scheduler.h"

#include <robot_core/loop_pacer.h>
#include <robot_core/priority_inheritance_mutex.h>
#include <robot_core/realtime.h>
#include <ros/ros.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace hcl_drivers {

// Commands of one board that arrive together (a drive's left and right wheel, published one
// after the other) go out in one exchange: a woken member waits this long for its siblings.
constexpr double kGatherCommands = 0.001;  // [s]
// Under simulated time, the shortest wait for the clock to move [s, wall]: /clock comes at most
// every 1 ms of wall time.
constexpr double kSimClockPoll = 0.0002;

// One polling thread servicing its members in turn, each when its own period is due.
class LoopScheduler::Loop {
 public:
  explicit Loop(std::string name) : name_(std::move(name)), thread_([this] { run(); }) {}

  ~Loop() {
    {
      std::lock_guard lk(mutex_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }

  void add(const std::string& member, double rate_hz, Work work) {
    std::lock_guard lk(mutex_);
    members_.push_back(std::make_shared<Member>(Member{member, robot_core::LoopPacer(1.0 / rate_hz), std::move(work), 0.0}));
    cv_.notify_all();
  }

  void wake(const std::string& member) {
    {
      std::lock_guard lk(mutex_);
      for (auto& m : members_)
        if (m->name == member && !m->pacer.woken()) {
          m->pacer.wake();
          m->woken_at = ros::Time::now().toSec();
        }
      ++wakes_;
    }
    cv_.notify_all();
  }

  // Returns true when the loop has no members left.
  bool remove(const std::string& member) {
    std::unique_lock lk(mutex_);
    members_.erase(std::remove_if(members_.begin(), members_.end(),
                                  [&](const std::shared_ptr<Member>& m) { return m->name == member; }),
                   members_.end());
    // The member may be running right now, outside the lock: wait until it returns.
    cv_.wait(lk, [&] { return running_ != member; });
    return members_.empty();
  }

  std::vector<std::string> names() const {
    std::lock_guard lk(mutex_);
    std::vector<std::string> out;
    for (const auto& m : members_) out.push_back(m->name);
    return out;
  }

 private:
  struct Member {
    std::string name;
    robot_core::LoopPacer pacer;  // its rate, and a wake by a command (robot_core/loop_pacer.h)
    Work work;
    double woken_at = 0.0;        // [s, ROS time] of the first wake since its last service

    double next() const { return pacer.woken() ? std::max(pacer.next(), woken_at + kGatherCommands) : pacer.next(); }
  };

  void run() {
    robot_core::enterRealtime("a bus loop");
    std::unique_lock lk(mutex_);
    while (!stop_) {
      const ros::Time now = ros::Time::now();
      if (members_.empty() || now.isZero()) {  // nothing to do, or simulated time not started yet
        cv_.wait_for(lk, std::chrono::milliseconds(10));
        continue;
      }
      double earliest = std::numeric_limits<double>::infinity();
      const auto snapshot = members_;  // members may leave while one is being serviced
      for (const auto& m : snapshot) {
        if (stop_) break;
        if (std::find(members_.begin(), members_.end(), m) == members_.end()) continue;  // left meanwhile
        const double t = ros::Time::now().toSec();
        if (t >= m->next()) {
          // The pacer never bursts to catch up missed cycles: a late run just sets the next.
          m->pacer.ran(t);
          running_ = m->name;
          lk.unlock();
          m->work();
          lk.lock();
          running_.clear();
          cv_.notify_all();
        }
        earliest = std::min(earliest, m->next());
      }
      if (stop_ || !std::isfinite(earliest)) continue;
      // A member woken while another was serviced is due now: go round again at once.
      const double wait = earliest - ros::Time::now().toSec();
      if (wait <= 0.0) continue;
      // Under simulated time, wall time and ROS time differ by the real-time factor: wake
      // often enough to notice the clock moving, but never spin on a clock that has not moved
      // (a due time inside the current /clock step: a real-time thread spinning there would
      // starve the thread that receives /clock). In wall time sleep exactly.
      const double wall_wait = ros::Time::isSimTime() ? std::clamp(wait, kSimClockPoll, 0.002) : wait;
      const unsigned long woken_before = wakes_;
      cv_.wait_for(lk, std::chrono::duration<double>(wall_wait), [&] { return stop_ || wakes_ != woken_before; });
    }
  }

  std::string name_;
  // Commands' wake() (normal-priority callback threads) and this real-time thread share them: a
  // priority-inheritance mutex, so a preempted waker never holds the loop up behind other work.
  mutable robot_core::PriorityInheritanceMutex mutex_;
  std::condition_variable_any cv_;
  std::vector<std::shared_ptr<Member>> members_;
  std::string running_;
  unsigned long wakes_ = 0;  // counts wake() calls: ends the loop's wait early
  bool stop_ = false;
  std::thread thread_;  // last: starts after everything above is constructed
};

void LoopScheduler::wake(const std::string& member) {
  std::shared_ptr<Loop> loop;
  {
    std::lock_guard<std::mutex> lk(mutex_);
    auto it = loop_of_member_.find(member);
    if (it == loop_of_member_.end()) return;
    auto l = loops_.find(it->second);
    if (l != loops_.end()) loop = l->second;
  }
  if (loop) loop->wake(member);
}

LoopScheduler& LoopScheduler::instance() {
  static LoopScheduler scheduler;
  return scheduler;
}

LoopScheduler::~LoopScheduler() {
  std::lock_guard<std::mutex> lk(mutex_);
  loops_.clear();
}

void LoopScheduler::join(const std::string& loop, const std::string& member, double rate_hz, Work work) {
  const std::string loop_name = loop.empty() ? "own:" + member : loop;
  std::shared_ptr<Loop> target;
  {
    std::lock_guard<std::mutex> lk(mutex_);
    auto& slot = loops_[loop_name];
    if (!slot) slot = std::make_shared<Loop>(loop_name);
    target = slot;
    loop_of_member_[member] = loop_name;
  }
  target->add(member, rate_hz, std::move(work));
}

void LoopScheduler::leave(const std::string& member) {
  std::shared_ptr<Loop> loop;
  std::string loop_name;
  {
    std::lock_guard<std::mutex> lk(mutex_);
    auto it = loop_of_member_.find(member);
    if (it == loop_of_member_.end()) return;
    loop_name = it->second;
    loop_of_member_.erase(it);
    loop = loops_[loop_name];
  }
  if (loop && loop->remove(member)) {
    std::lock_guard<std::mutex> lk(mutex_);
    auto it = loops_.find(loop_name);
    if (it != loops_.end() && it->second == loop && loop->names().empty()) loops_.erase(it);
  }
}

std::vector<std::string> LoopScheduler::members(const std::string& loop) const {
  std::lock_guard<std::mutex> lk(mutex_);
  auto it = loops_.find(loop);
  return it == loops_.end() ? std::vector<std::string>{} : it->second->names();
}

std::string LoopScheduler::loopOf(const std::string& member) const {
  std::lock_guard<std::mutex> lk(mutex_);
  auto it = loop_of_member_.find(member);
  return it == loop_of_member_.end() ? std::string() : it->second;
}

}  // namespace hcl_drivers
