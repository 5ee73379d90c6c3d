#include <gtest/gtest.h>
#include <ros/time.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

#include "hcl_drivers/loop_scheduler.h"

using hcl_drivers::LoopScheduler;

namespace {
void sleepFor(double s) { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }
}  // namespace

TEST(LoopScheduler, PrivateLoopRunsAtItsRate) {
  LoopScheduler s;
  std::atomic<int> n{0};
  s.join("", "a", 100.0, [&] { ++n; });
  sleepFor(1.0);
  s.leave("a");
  // Wall-clock loop on a loaded 2-core machine: a loose band, but a wrong rate (10 or 1000) fails.
  EXPECT_GT(n.load(), 60);
  EXPECT_LT(n.load(), 130);
}

TEST(LoopScheduler, GroupMembersShareOneThreadAndNeverOverlap) {
  LoopScheduler s;
  std::atomic<int> running{0}, overlaps{0}, a{0}, b{0};
  std::mutex ids_mutex;
  std::vector<std::thread::id> ids;
  auto work = [&](std::atomic<int>& counter) {
    if (running.fetch_add(1) != 0) ++overlaps;
    {
      std::lock_guard<std::mutex> lk(ids_mutex);
      ids.push_back(std::this_thread::get_id());
    }
    sleepFor(0.001);
    ++counter;
    running.fetch_sub(1);
  };
  s.join("i2c-1", "a", 50.0, [&] { work(a); });
  s.join("i2c-1", "b", 25.0, [&] { work(b); });
  EXPECT_EQ(s.members("i2c-1"), (std::vector<std::string>{"a", "b"}));
  sleepFor(1.0);
  s.leave("a");
  s.leave("b");
  EXPECT_EQ(overlaps.load(), 0);
  for (const auto& id : ids) EXPECT_EQ(id, ids.front());
  // Each member at its own rate within the shared loop.
  EXPECT_GT(a.load(), 30);
  EXPECT_GT(b.load(), 15);
  EXPECT_LT(b.load(), a.load());
  EXPECT_TRUE(s.members("i2c-1").empty());
}

TEST(LoopScheduler, LeaveWaitsForRunningWorkAndStopsIt) {
  LoopScheduler s;
  std::atomic<bool> inside{false};
  std::atomic<int> after_leave{0};
  std::atomic<bool> left{false};
  s.join("", "slow", 100.0, [&] {
    inside = true;
    sleepFor(0.05);
    if (left) ++after_leave;
    inside = false;
  });
  while (!inside) sleepFor(0.001);
  s.leave("slow");
  left = true;
  EXPECT_FALSE(inside.load());
  sleepFor(0.1);
  EXPECT_EQ(after_leave.load(), 0);
}

int main(int argc, char** argv) {
  ros::Time::init();  // wall time, no master needed
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}

TEST(LoopScheduler, AWokenMemberIsServicedWithoutWaitingForItsPeriod) {
  // A 2 Hz board woken by a command: serviced within milliseconds, not at its next 500 ms tick;
  // a flood of wakes does not raise its rate above the configured one (plus the pacer's burst).
  LoopScheduler s;
  std::atomic<int> n{0};
  std::mutex m;
  std::vector<std::chrono::steady_clock::time_point> runs;
  s.join("", "slow_board", 2.0, [&] {
    std::lock_guard<std::mutex> lk(m);
    runs.push_back(std::chrono::steady_clock::now());
    ++n;
  });
  sleepFor(0.2);  // its first run is at once; the next one would be 0.5 s later
  const auto woken = std::chrono::steady_clock::now();
  s.wake("slow_board");  // the pacer's spare token serves this one at once
  sleepFor(0.05);
  {
    std::lock_guard<std::mutex> lk(m);
    ASSERT_EQ(runs.size(), 2u);
    const double delay = std::chrono::duration<double>(runs.back() - woken).count();
    EXPECT_LT(delay, 0.03);  // 1 ms of command gathering plus scheduling; the tick was 300 ms away
  }
  for (int i = 0; i < 100; ++i) {  // 1 s of wakes every 10 ms
    s.wake("slow_board");
    sleepFor(0.01);
  }
  s.leave("slow_board");
  EXPECT_LE(n.load(), 2 + 2 + 2);  // the two above, 2 Hz over 1 s, and the bucket's spare token
}
