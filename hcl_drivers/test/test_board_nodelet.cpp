// The Board framework around a probe board: polling at ~rate, errors counted, STALE and a
// single halt() when the board stops answering, recovery, halt() on unload, bad ~rate, and its
// /diagnostics: once a period while the level holds, at once when it changes.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <atomic>
#include <cstdio>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "hcl_drivers/board_nodelet.h"

namespace {

// Times are ROS time, the clock the framework checks and reports on; with no simulated clock in
// this test it runs with the wall, so the latencies below are what a user sees.

struct Probe {
  std::atomic<int> services{0};
  std::atomic<int> halts{0};
  std::atomic<int> mode{0};  // 0 answer, 1 no answer, 2 throw
  std::atomic<int> fail_next{0};  // in mode 0: this many services fail first
};
Probe probe;

class ProbeBoard : public hcl_drivers::Board {
 public:
  void configure(const robot_core::Params&) override {}
  void init(hcl_drivers::BoardContext&) override {}
  bool service() override {
    ++probe.services;
    if (probe.mode == 2) throw std::runtime_error("probe exploded");
    if (probe.mode == 1 || (probe.mode == 0 && probe.fail_next.fetch_sub(1) > 0)) {
      fail("probe not answering");
      return false;
    }
    return true;
  }
  void halt() override { ++probe.halts; }
};

using ProbeNodelet = hcl_drivers::BoardNodelet<ProbeBoard>;

class DiagnosticsWatch {
 public:
  explicit DiagnosticsWatch(const std::string& name_part) : part_(name_part) {
    sub_ = ros::NodeHandle().subscribe("/diagnostics", 100, &DiagnosticsWatch::cb, this);
  }
  int level() {
    std::lock_guard<std::mutex> lk(m_);
    return level_;
  }
  std::string message() {
    std::lock_guard<std::mutex> lk(m_);
    return message_;
  }
  struct Seen {
    ros::Time at;  // when it arrived
    int level;
    std::string message;
  };
  // Every status received so far.
  std::vector<Seen> history() {
    std::lock_guard<std::mutex> lk(m_);
    return history_;
  }
  // Waits up to `timeout` s for a status at `level` that arrived after `since`; when it came.
  bool waitFor(int level, double timeout, const ros::Time& since, ros::Time* at = nullptr) {
    const ros::Time end = ros::Time::now() + ros::Duration(timeout);
    do {
      for (const auto& seen : history())
        if (seen.at > since && seen.level == level) {
          if (at) *at = seen.at;
          return true;
        }
      ros::Duration(0.01).sleep();
    } while (ros::Time::now() < end);
    return false;
  }
  // Waits up to `timeout` s for the level; returns true when seen.
  bool waitFor(int level, double timeout) {
    const ros::Time end = ros::Time::now() + ros::Duration(timeout);
    while (ros::Time::now() < end) {
      if (this->level() == level) return true;
      ros::Duration(0.01).sleep();
    }
    return false;
  }

 private:
  void cb(const diagnostic_msgs::DiagnosticArray::ConstPtr& a) {
    for (const auto& s : a->status)
      if (s.name.find(part_) != std::string::npos) {
        std::lock_guard<std::mutex> lk(m_);
        level_ = s.level;
        message_ = s.message;
        history_.push_back({ros::Time::now(), s.level, s.message});
      }
  }
  std::string part_;
  std::mutex m_;
  int level_ = -1;
  std::string message_;
  std::vector<Seen> history_;
  ros::Subscriber sub_;
};

std::unique_ptr<ProbeNodelet> load(const std::string& name, double rate, double stale_timeout = 0.3) {
  ros::param::set(name + "/rate", rate);
  ros::param::set(name + "/stale_timeout", stale_timeout);
  auto n = std::make_unique<ProbeNodelet>();
  n->init(name, nodelet::M_string(), nodelet::V_string());
  return n;
}

}  // namespace

TEST(BoardNodelet, PollsAtRateReportsStaleHaltsOnceAndRecovers) {
  probe.mode = 0;
  DiagnosticsWatch diag("probe_board");
  auto board = load("/probe_board", 100.0);
  ros::Duration(1.0).sleep();
  const int polled = probe.services.load();
  EXPECT_GT(polled, 60);
  EXPECT_LT(polled, 140);
  ASSERT_TRUE(diag.waitFor(diagnostic_msgs::DiagnosticStatus::OK, 1.0)) << diag.message();
  EXPECT_EQ(probe.halts.load(), 0);

  probe.mode = 1;  // the board stops answering
  EXPECT_TRUE(diag.waitFor(diagnostic_msgs::DiagnosticStatus::STALE, 1.0)) << diag.message();
  EXPECT_NE(diag.message().find("probe not answering"), std::string::npos) << diag.message();
  ros::Duration(0.5).sleep();
  EXPECT_EQ(probe.halts.load(), 1) << "halt() exactly once when the board goes stale";

  probe.mode = 0;  // it answers again
  EXPECT_TRUE(diag.waitFor(diagnostic_msgs::DiagnosticStatus::OK, 1.0)) << diag.message();

  board.reset();  // unload
  EXPECT_EQ(probe.halts.load(), 2) << "halt() on unload";
  const int after = probe.services.load();
  ros::Duration(0.2).sleep();
  EXPECT_EQ(probe.services.load(), after) << "no service() after unload";
}

TEST(BoardNodelet, AnExceptionInServiceIsAnErrorNotACrash) {
  probe.mode = 2;
  DiagnosticsWatch diag("probe_throw");
  auto board = load("/probe_throw", 50.0);
  EXPECT_TRUE(diag.waitFor(diagnostic_msgs::DiagnosticStatus::STALE, 1.5)) << diag.message();
  EXPECT_NE(diag.message().find("probe exploded"), std::string::npos) << diag.message();
  probe.mode = 0;
  EXPECT_TRUE(diag.waitFor(diagnostic_msgs::DiagnosticStatus::OK, 1.0)) << diag.message();
}

TEST(BoardNodelet, ReportsOnceAPeriodWhileTheLevelHolds) {
  using diagnostic_msgs::DiagnosticStatus;
  probe.mode = 0;
  probe.fail_next = 0;
  DiagnosticsWatch diag("probe_cadence");
  auto board = load("/probe_cadence", 10.0);  // ~diagnostic_period at its default, 1 s
  ASSERT_TRUE(diag.waitFor(DiagnosticStatus::OK, 2.0)) << diag.message();
  const ros::Time t0 = ros::Time::now();
  ros::Duration(3.0).sleep();
  int steady = 0;
  for (const auto& seen : diag.history()) steady += seen.at > t0 && seen.level == DiagnosticStatus::OK;
  EXPECT_GE(steady, 2) << "a status at least once a period while nothing changes";
  EXPECT_LE(steady, 4) << "no more than once a period while the level holds";
}

TEST(BoardNodelet, ALevelChangeIsPublishedAtOnce) {
  using diagnostic_msgs::DiagnosticStatus;
  probe.mode = 0;
  probe.fail_next = 0;
  ros::param::set("/probe_change/diagnostic_period", 10.0);  // only a change can be published in time
  DiagnosticsWatch diag("probe_change");
  auto board = load("/probe_change", 100.0);
  ASSERT_TRUE(diag.waitFor(DiagnosticStatus::OK, 2.0)) << diag.message();

  // The board stops answering: ERROR after ~failures_for_error (3) exchanges, STALE after
  // ~stale_timeout (0.3 s); each change goes out within a check (0.05 s), not a period.
  const ros::Time t0 = ros::Time::now();
  probe.mode = 1;
  ros::Time stale_at;
  ASSERT_TRUE(diag.waitFor(DiagnosticStatus::STALE, 2.0, t0, &stale_at)) << diag.message();
  ros::Time first_change;
  for (const auto& seen : diag.history())
    if (seen.at > t0 && seen.level != DiagnosticStatus::OK) {
      first_change = seen.at;
      break;
    }
  const double latency = (first_change - t0).toSec();
  std::printf("level change published %.3f s after the board stopped answering\n", latency);
  EXPECT_LT(latency, 0.2) << "a level change reaches /diagnostics within 0.2 s";

  const ros::Time t1 = ros::Time::now();
  probe.mode = 0;
  ros::Time ok_at;
  ASSERT_TRUE(diag.waitFor(DiagnosticStatus::OK, 2.0, t1, &ok_at)) << diag.message();
  EXPECT_LT((ok_at - t1).toSec(), 0.2) << "back to OK within 0.2 s";
}

TEST(BoardNodelet, TwoFailedExchangesInARowAreAWarningNotAnError) {
  using diagnostic_msgs::DiagnosticStatus;
  probe.mode = 0;
  probe.fail_next = 0;
  DiagnosticsWatch diag("probe_flaky");
  // 10 Hz: each failure spans two checks; never STALE within these few failures.
  auto board = load("/probe_flaky", 10.0, 5.0);
  ASSERT_TRUE(diag.waitFor(DiagnosticStatus::OK, 2.0)) << diag.message();
  const ros::Time t0 = ros::Time::now();
  probe.fail_next = 2;
  ros::Time warned;
  ASSERT_TRUE(diag.waitFor(DiagnosticStatus::WARN, 1.0, t0, &warned)) << "two failures in a row are seen: " << diag.message();
  EXPECT_TRUE(diag.waitFor(DiagnosticStatus::OK, 1.0, warned)) << diag.message();
  for (const auto& seen : diag.history()) {
    if (seen.at > t0) {
      EXPECT_LT(seen.level, DiagnosticStatus::ERROR) << "two failed exchanges called: " << seen.message;
    }
  }

  const ros::Time t1 = ros::Time::now();
  probe.fail_next = 4;  // from the third, an ERROR
  ros::Time erred;
  ASSERT_TRUE(diag.waitFor(DiagnosticStatus::ERROR, 1.5, t1, &erred)) << diag.message();
  EXPECT_TRUE(diag.waitFor(DiagnosticStatus::OK, 1.5, erred)) << diag.message();
}

TEST(BoardNodelet, NonPositiveRateIsRefused) {
  ros::param::set("/probe_bad/rate", 0.0);
  ProbeNodelet n;
  EXPECT_THROW(n.init("/probe_bad", nodelet::M_string(), nodelet::V_string()), robot_core::ParameterError);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_board_nodelet");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
