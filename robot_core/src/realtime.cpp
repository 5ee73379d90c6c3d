#include "robot_core/realtime.h"

#include <pthread.h>
#include <ros/console.h>
#include <sched.h>
#include <sys/mman.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <mutex>

#ifndef MCL_ONFAULT
#define MCL_ONFAULT 4  // Linux 4.4 (glibc's header may predate it)
#endif

namespace robot_core {

namespace {
std::atomic<int> process_priority{0};
std::once_flag memory_locked, warned;
}  // namespace

void setRealtimePriority(int priority) { process_priority = priority; }
int realtimePriority() { return process_priority; }

bool makeThreadRealtime(int priority, std::string* why) {
  if (priority < 1 || priority > 99) {
    if (why) *why = "priority " + std::to_string(priority) + " is not a SCHED_FIFO priority 1..99";
    return false;
  }
  sched_param param{};
  param.sched_priority = priority;
  const int err = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  if (err != 0) {
    if (why)
      *why = std::string("SCHED_FIFO ") + std::to_string(priority) + " refused: " + std::strerror(err) +
             (err == EPERM ? " (run as root, or grant the user rtprio in /etc/security/limits.d or the service's "
                             "LimitRTPRIO)"
                           : "");
    return false;
  }
  std::call_once(memory_locked, [] {
    // Locked as touched: thread stacks are not committed whole, and nothing is ever paged out.
    if (mlockall(MCL_CURRENT | MCL_FUTURE | MCL_ONFAULT) != 0)
      ROS_WARN("real-time: memory not locked (%s): a page fault may delay a real-time thread", std::strerror(errno));
  });
  return true;
}

bool enterRealtime(const char* role) {
  const int priority = process_priority;
  if (priority <= 0) return true;
  std::string why;
  if (makeThreadRealtime(priority, &why)) return true;
  std::call_once(warned, [&] {
    ROS_WARN("real-time: %s runs at normal priority: %s. Under load it may answer late.", role, why.c_str());
  });
  return false;
}

}  // namespace robot_core
