// robot_core/realtime.h: a thread gets SCHED_FIFO where the process may have it; where it may
// not, enterRealtime() says so once with a WARN and the thread runs on at normal priority.
// Each case runs in a child process: the scheduling class, the locked memory and the once-only
// WARN are per process, and the refused case gives up root for good.
#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>

#include "robot_core/priority_inheritance_mutex.h"
#include "robot_core/realtime.h"

namespace {

struct ChildResult {
  int exit_code = -1;
  std::string stderr_text;
};

// Runs `body` in a child whose stderr (rosconsole's WARN) is captured; the child exits with
// body()'s value.
template <typename Body>
ChildResult runInChild(Body body) {
  int fds[2];
  if (pipe(fds) != 0) return {};
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    dup2(fds[1], STDERR_FILENO);
    dup2(fds[1], STDOUT_FILENO);
    _exit(body());
  }
  close(fds[1]);
  ChildResult result;
  char buf[4096];
  ssize_t n;
  while ((n = read(fds[0], buf, sizeof(buf))) > 0) result.stderr_text.append(buf, static_cast<size_t>(n));
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 100 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  return result;
}

size_t count(const std::string& text, const std::string& word) {
  size_t n = 0;
  for (size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + word.size())) ++n;
  return n;
}

bool mayHaveRealtime() {
  sched_param keep{};
  int policy = 0;
  pthread_getschedparam(pthread_self(), &policy, &keep);
  std::string why;
  const bool ok = robot_core::makeThreadRealtime(1, &why);
  pthread_setschedparam(pthread_self(), policy, &keep);
  return ok;
}

}  // namespace

TEST(Realtime, RefusedFallsBackWithOneWarnAndNormalPriority) {
  const ChildResult r = runInChild([] {
    // No right to real time: a zero RLIMIT_RTPRIO and, for root, no capabilities (a uid without
    // root keeps none).
    rlimit none{0, 0};
    if (setrlimit(RLIMIT_RTPRIO, &none) != 0) return 10;
    if (geteuid() == 0 && (setgid(65534) != 0 || setuid(65534) != 0)) return 11;
    robot_core::setRealtimePriority(30);
    if (robot_core::enterRealtime("a test loop")) return 12;      // refused ...
    if (robot_core::enterRealtime("another test loop")) return 13;  // ... every time
    if (sched_getscheduler(0) != SCHED_OTHER) return 14;           // and still normal
    std::string why;
    if (robot_core::makeThreadRealtime(30, &why) || why.find("refused") == std::string::npos) return 15;
    return 0;
  });
  EXPECT_EQ(r.exit_code, 0) << r.stderr_text;
  EXPECT_EQ(count(r.stderr_text, "real-time: a test loop runs at normal priority"), 1u) << r.stderr_text;
  EXPECT_EQ(count(r.stderr_text, "real-time:"), 1u) << "one WARN per process: " << r.stderr_text;
  EXPECT_NE(r.stderr_text.find("LimitRTPRIO"), std::string::npos) << "the WARN says how to grant it: " << r.stderr_text;
}

TEST(Realtime, PriorityZeroIsNormalSchedulingWithoutWarn) {
  const ChildResult r = runInChild([] {
    robot_core::setRealtimePriority(0);
    if (!robot_core::enterRealtime("a test loop")) return 20;
    return sched_getscheduler(0) == SCHED_OTHER ? 0 : 21;
  });
  EXPECT_EQ(r.exit_code, 0) << r.stderr_text;
  EXPECT_EQ(count(r.stderr_text, "real-time:"), 0u) << r.stderr_text;
}

TEST(Realtime, GrantedThreadRunsFifoAtTheProcessPriority) {
  if (!mayHaveRealtime()) GTEST_SKIP() << "this process may not use SCHED_FIFO (not root, no rtprio)";
  const ChildResult r = runInChild([] {
    robot_core::setRealtimePriority(7);
    if (!robot_core::enterRealtime("a test loop")) return 30;
    sched_param param{};
    int policy = 0;
    pthread_getschedparam(pthread_self(), &policy, &param);
    return policy == SCHED_FIFO && param.sched_priority == 7 ? 0 : 31;
  });
  EXPECT_EQ(r.exit_code, 0) << r.stderr_text;
  EXPECT_EQ(count(r.stderr_text, "runs at normal priority"), 0u) << r.stderr_text;
}

TEST(Realtime, OutOfRangePriorityIsRefusedWithItsReason) {
  std::string why;
  EXPECT_FALSE(robot_core::makeThreadRealtime(0, &why));
  EXPECT_NE(why.find("1..99"), std::string::npos) << why;
  EXPECT_FALSE(robot_core::makeThreadRealtime(100, &why));
}

namespace {

// The calling thread's scheduling priority as the kernel uses it (the 18th field of
// /proc/thread-self/stat): 20 for a normal thread at nice 0, -1 - p for SCHED_FIFO p, and so
// the priority a holder of a priority-inheritance mutex was lent.
int kernelPriority() {
  std::ifstream f("/proc/thread-self/stat");
  std::string stat((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  std::istringstream rest(stat.substr(stat.rfind(')') + 2));  // after "pid (comm) "
  std::string field;
  for (int i = 3; i <= 18 && rest >> field; ++i) {
  }
  return std::stoi(field);
}

}  // namespace

TEST(PriorityInheritanceMutex, LocksLikeAMutex) {
  robot_core::PriorityInheritanceMutex m;
  {
    std::lock_guard<robot_core::PriorityInheritanceMutex> lk(m);
    std::atomic<bool> got{true};
    std::thread other([&] { got = m.try_lock(); });
    other.join();
    EXPECT_FALSE(got) << "try_lock succeeded on a held mutex";
  }
  EXPECT_TRUE(m.try_lock());
  m.unlock();
}

TEST(PriorityInheritanceMutex, HolderRunsAtTheWaitersPriority) {
  if (!mayHaveRealtime()) GTEST_SKIP() << "this process may not use SCHED_FIFO (not root, no rtprio)";
  robot_core::PriorityInheritanceMutex m;
  m.lock();  // held by this normal thread
  const int before = kernelPriority();
  std::atomic<bool> waiting{false}, done{false}, refused{false};
  std::thread waiter([&] {
    std::string why;
    if (!robot_core::makeThreadRealtime(10, &why)) {  // allowed a lower priority only
      refused = true;
      return;
    }
    waiting = true;
    m.lock();
    m.unlock();
    done = true;
  });
  while (!waiting && !refused) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  if (refused) {
    m.unlock();
    waiter.join();
    GTEST_SKIP() << "SCHED_FIFO 10 not allowed here";
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the waiter is blocked on the mutex
  const int lent = kernelPriority();
  m.unlock();
  waiter.join();
  EXPECT_TRUE(done);
  EXPECT_GE(before, 0) << "this thread runs at normal priority (0..39, 20 at nice 0)";
  EXPECT_EQ(lent, -11) << "the holder did not get the SCHED_FIFO 10 waiter's priority";
  EXPECT_EQ(kernelPriority(), before) << "the lent priority outlived the lock";
}
