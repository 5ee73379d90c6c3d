// The Board framework around a probe board: polling at ~rate, errors counted, STALE and a
// single halt() when the board stops answering, recovery, halt() on unload, bad ~rate.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "hcl_drivers/board_nodelet.h"

namespace {

struct Probe {
  std::atomic<int> services{0};
  std::atomic<int> halts{0};
  std::atomic<int> mode{0};  // 0 answer, 1 no answer, 2 throw
};
Probe probe;

class ProbeBoard : public hcl_drivers::Board {
 public:
  void init(hcl_drivers::BoardContext&) override {}
  bool service() override {
    ++probe.services;
    if (probe.mode == 2) throw std::runtime_error("probe exploded");
    if (probe.mode == 1) {
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
  // Waits up to `timeout` s for the level; returns true when seen.
  bool waitFor(int level, double timeout) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
    while (ros::WallTime::now() < end) {
      if (this->level() == level) return true;
      ros::WallDuration(0.01).sleep();
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
      }
  }
  std::string part_;
  std::mutex m_;
  int level_ = -1;
  std::string message_;
  ros::Subscriber sub_;
};

std::unique_ptr<ProbeNodelet> load(const std::string& name, double rate) {
  ros::param::set(name + "/rate", rate);
  ros::param::set(name + "/stale_timeout", 0.3);
  auto n = std::make_unique<ProbeNodelet>();
  n->init(name, nodelet::M_string(), nodelet::V_string());
  return n;
}

}  // namespace

TEST(BoardNodelet, PollsAtRateReportsStaleHaltsOnceAndRecovers) {
  probe.mode = 0;
  DiagnosticsWatch diag("probe_board");
  auto board = load("/probe_board", 100.0);
  ros::WallDuration(1.0).sleep();
  const int polled = probe.services.load();
  EXPECT_GT(polled, 60);
  EXPECT_LT(polled, 140);
  ASSERT_TRUE(diag.waitFor(diagnostic_msgs::DiagnosticStatus::OK, 1.0)) << diag.message();
  EXPECT_EQ(probe.halts.load(), 0);

  probe.mode = 1;  // the board stops answering
  EXPECT_TRUE(diag.waitFor(diagnostic_msgs::DiagnosticStatus::STALE, 1.0)) << diag.message();
  EXPECT_NE(diag.message().find("probe not answering"), std::string::npos) << diag.message();
  ros::WallDuration(0.5).sleep();
  EXPECT_EQ(probe.halts.load(), 1) << "halt() exactly once when the board goes stale";

  probe.mode = 0;  // it answers again
  EXPECT_TRUE(diag.waitFor(diagnostic_msgs::DiagnosticStatus::OK, 1.0)) << diag.message();

  board.reset();  // unload
  EXPECT_EQ(probe.halts.load(), 2) << "halt() on unload";
  const int after = probe.services.load();
  ros::WallDuration(0.2).sleep();
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
