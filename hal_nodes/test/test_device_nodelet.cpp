// The Device framework around a probe effector: refresh at ~rate, unavailability reported,
// /effectors/deactivated freezes it at once and lifts again, halt() on unload, bad ~rate.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>
#include <std_srvs/Trigger.h>

#include <atomic>
#include <memory>
#include <mutex>

#include "hal_nodes/device_nodelet.h"
#include "hal_nodes/effector_supervisor.h"

namespace {

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

int waitForLevel(const std::string& part, int level, double timeout, std::string* message) {
  std::mutex m;
  int seen = -1;
  std::string msg;
  ros::Subscriber sub = ros::NodeHandle().subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 100, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& a) {
        for (const auto& s : a->status)
          if (s.name.find(part) != std::string::npos) {
            std::lock_guard<std::mutex> lk(m);
            seen = s.level;
            msg = s.message;
          }
      });
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(timeout);
  while (ros::WallTime::now() < end) {
    {
      std::lock_guard<std::mutex> lk(m);
      if (seen == level) break;
    }
    ros::WallDuration(0.01).sleep();
  }
  std::lock_guard<std::mutex> lk(m);
  if (message) *message = msg;
  return seen;
}

}  // namespace

TEST(DeviceNodelet, RefreshesReportsAndFollowsTheEffectorSwitch) {
  ros::NodeHandle nh;
  hal_nodes::EffectorSupervisor supervisor(nh);
  ros::param::set("/probe_device/rate", 50.0);
  auto device = std::make_unique<ProbeNodelet>();
  device->init("/probe_device", nodelet::M_string(), nodelet::V_string());
  ros::WallDuration(1.0).sleep();
  EXPECT_GT(probe.refreshes.load(), 30);
  EXPECT_LT(probe.refreshes.load(), 70);
  std::string message;
  EXPECT_EQ(waitForLevel("probe_device", diagnostic_msgs::DiagnosticStatus::OK, 1.0, &message),
            diagnostic_msgs::DiagnosticStatus::OK) << message;

  probe.available = false;
  EXPECT_EQ(waitForLevel("probe_device", diagnostic_msgs::DiagnosticStatus::ERROR, 1.0, &message),
            diagnostic_msgs::DiagnosticStatus::ERROR);
  EXPECT_NE(message.find("probe input missing"), std::string::npos) << message;
  probe.available = true;

  std_srvs::Trigger call;
  ASSERT_TRUE(ros::service::call("/effectors/deactivate", call));
  EXPECT_TRUE(call.response.success);
  const ros::WallTime t0 = ros::WallTime::now();
  while (probe.deactivations == 0 && ros::WallTime::now() - t0 < ros::WallDuration(1.0)) ros::WallDuration(0.001).sleep();
  EXPECT_EQ(probe.deactivations.load(), 1);
  EXPECT_LT((ros::WallTime::now() - t0).toSec(), 0.05) << "deactivation within one 50 Hz period and some";
  EXPECT_EQ(waitForLevel("probe_device", diagnostic_msgs::DiagnosticStatus::WARN, 1.0, &message),
            diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_EQ(message, "deactivated");

  ASSERT_TRUE(ros::service::call("/effectors/activate", call));
  const ros::WallTime t1 = ros::WallTime::now();
  while (probe.reactivations == 0 && ros::WallTime::now() - t1 < ros::WallDuration(1.0)) ros::WallDuration(0.001).sleep();
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
