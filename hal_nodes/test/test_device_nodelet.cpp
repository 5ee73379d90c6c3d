// The Device framework around a probe effector: refresh at ~rate, unavailability reported,
// /effectors/deactivated freezes it at once and lifts again, halt() on unload, bad ~rate; its
// status is published at once when its level changes.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>
#include <std_srvs/Trigger.h>

#include <atomic>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "hal_nodes/device_nodelet.h"
#include "hal_nodes/effector_supervisor.h"

namespace {

// Times are ROS time, the clock the framework checks and reports on; with no simulated clock in
// this test it runs with the wall, so the latencies below are what a user sees.

struct Probe {
  std::atomic<int> refreshes{0};
  std::atomic<int> commands_while_inactive{0};
  std::atomic<int> deactivations{0};
  std::atomic<int> reactivations{0};
  std::atomic<int> halts{0};
  std::atomic<bool> available{true};
};
Probe probe;

class ProbeEffector : public hal_nodes::Effector {
 public:
  void configure(const robot_core::Params&) override {}
  void init(hal_nodes::DeviceContext&) override {}
  void refresh() override {
    ++probe.refreshes;
    if (probe.available) setAvailable();
    else setUnavailable("probe input missing");
    if (!active()) return;
  }
  void deactivate() override { ++probe.deactivations; }
  void reactivate() override { ++probe.reactivations; }
  void halt() override { ++probe.halts; }
};

using ProbeNodelet = hal_nodes::DeviceNodelet<ProbeEffector>;

// The statuses of a device on /diagnostics, watched from construction on.
class StatusWatch {
 public:
  explicit StatusWatch(const std::string& part) : part_(part) {
    sub_ = ros::NodeHandle().subscribe<diagnostic_msgs::DiagnosticArray>(
        "/diagnostics", 100, [this](const diagnostic_msgs::DiagnosticArray::ConstPtr& a) {
          for (const auto& s : a->status)
            if (s.name.find(part_) != std::string::npos) {
              std::lock_guard<std::mutex> lk(m_);
              seen_.push_back({ros::Time::now(), s.level, s.message});
            }
        });
    ros::Duration(0.3).sleep();  // connected before anything is asked of it
  }
  // Waits up to `timeout` s for a status at `level` that arrived after `since`: when it came
  // (zero: none came), and its message.
  ros::Time waitFor(int level, double timeout, const ros::Time& since, std::string* message) {
    const ros::Time end = ros::Time::now() + ros::Duration(timeout);
    do {
      {
        std::lock_guard<std::mutex> lk(m_);
        for (const auto& s : seen_)
          if (s.at > since && s.level == level) {
            if (message) *message = s.message;
            return s.at;
          }
        if (message) *message = seen_.empty() ? "(no status)" : seen_.back().message;
      }
      ros::Duration(0.005).sleep();
    } while (ros::Time::now() < end);
    return ros::Time();
  }

 private:
  struct Seen {
    ros::Time at;
    int level;
    std::string message;
  };
  std::string part_;
  std::mutex m_;
  std::vector<Seen> seen_;
  ros::Subscriber sub_;
};

}  // namespace

TEST(DeviceNodelet, RefreshesReportsAndFollowsTheEffectorSwitch) {
  ros::NodeHandle nh;
  hal_nodes::EffectorSupervisor supervisor(nh);
  ros::param::set("/probe_device/rate", 50.0);
  StatusWatch status("probe_device");
  ros::param::set("/probe_device/diagnostic_period", 10.0);  // only a change can be published in time
  const ros::Time t_start = ros::Time::now();
  auto device = std::make_unique<ProbeNodelet>();
  device->init("/probe_device", nodelet::M_string(), nodelet::V_string());
  ros::Duration(1.0).sleep();
  EXPECT_GT(probe.refreshes.load(), 30);
  EXPECT_LT(probe.refreshes.load(), 70);
  std::string message;
  EXPECT_FALSE(status.waitFor(diagnostic_msgs::DiagnosticStatus::OK, 1.0, t_start, &message).isZero()) << message;

  // A level change is published at once (within a 0.05 s check), not at the next report.
  const ros::Time t_lost = ros::Time::now();
  probe.available = false;
  const ros::Time lost_at = status.waitFor(diagnostic_msgs::DiagnosticStatus::ERROR, 2.0, t_lost, &message);
  ASSERT_FALSE(lost_at.isZero()) << message;
  std::printf("level change published %.3f s after the device became unavailable\n", (lost_at - t_lost).toSec());
  EXPECT_LT((lost_at - t_lost).toSec(), 0.2) << "a level change reaches /diagnostics within 0.2 s";
  EXPECT_NE(message.find("probe input missing"), std::string::npos) << message;
  const ros::Time t_back = ros::Time::now();
  probe.available = true;
  const ros::Time back_at = status.waitFor(diagnostic_msgs::DiagnosticStatus::OK, 2.0, t_back, &message);
  ASSERT_FALSE(back_at.isZero()) << message;
  EXPECT_LT((back_at - t_back).toSec(), 0.2) << "and so does the way back";

  std_srvs::Trigger call;
  const ros::Time t_call = ros::Time::now();
  ASSERT_TRUE(ros::service::call("/effectors/deactivate", call));
  EXPECT_TRUE(call.response.success);
  const ros::Time t0 = ros::Time::now();
  while (probe.deactivations == 0 && ros::Time::now() - t0 < ros::Duration(1.0)) ros::Duration(0.001).sleep();
  EXPECT_EQ(probe.deactivations.load(), 1);
  EXPECT_LT((ros::Time::now() - t0).toSec(), 0.05) << "deactivation within one 50 Hz period and some";
  EXPECT_FALSE(status.waitFor(diagnostic_msgs::DiagnosticStatus::WARN, 1.0, t_call, &message).isZero()) << message;
  EXPECT_EQ(message, "deactivated");

  ASSERT_TRUE(ros::service::call("/effectors/activate", call));
  const ros::Time t1 = ros::Time::now();
  while (probe.reactivations == 0 && ros::Time::now() - t1 < ros::Duration(1.0)) ros::Duration(0.001).sleep();
  EXPECT_EQ(probe.reactivations.load(), 1);

  device.reset();
  EXPECT_EQ(probe.halts.load(), 1);
}

TEST(DeviceNodelet, NonPositiveRateIsRefused) {
  ros::param::set("/probe_bad/rate", -2.0);
  ProbeNodelet n;
  EXPECT_THROW(n.init("/probe_bad", nodelet::M_string(), nodelet::V_string()), robot_core::ParameterError);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_device_nodelet");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
