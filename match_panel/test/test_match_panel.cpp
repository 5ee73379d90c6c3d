// The panel's model against the whole simulated 2009 robot (match_panel.test): everything the
// panel shows and every button, as rviz would use them, without Qt.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>

#include <algorithm>
#include <atomic>
#include <functional>

#include "match_panel/panel_model.h"

using match_panel::PanelModel;
using match_panel::ServiceResult;
using match_panel::Snapshot;

namespace {

// Polls `condition` on the wall clock (the simulation may run at any speed) for `timeout` s.
bool waitFor(const std::function<bool()>& condition, double timeout) {
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout);
  while (ros::ok() && ros::WallTime::now() < deadline) {
    if (condition()) return true;
    ros::WallDuration(0.05).sleep();
  }
  return condition();
}

std::string describe(const Snapshot& s) {
  return "state=" + s.state + " strategy=" + s.strategy + " clock=" + s.clock + " path=" + s.active_path +
         " readiness=" + s.readiness;
}

}  // namespace

TEST(MatchPanel, DrivesTheSimulatedRobot) {
  PanelModel model;
  auto now = [] { return ros::Time::now(); };
  Snapshot s;

  // The brain's status, its strategy and the robot's name from config.
  ASSERT_TRUE(waitFor([&] { s = model.snapshot(now()); return s.have_status && s.state == "waiting_for_start"; }, 40.0))
      << describe(s);
  EXPECT_EQ("homologation", s.strategy);
  EXPECT_EQ("eurobot2009", s.robot_name);
  EXPECT_NE("\xe2\x80\x94", s.clock);  // a timed match shows its full length before the start

  // The strategy list: refused switch to "", nothing switched.
  ServiceResult r = model.refreshStrategies();
  ASSERT_TRUE(r.ok) << r.message;
  s = model.snapshot(now());
  ASSERT_NE(s.strategies.end(), std::find(s.strategies.begin(), s.strategies.end(), "match"));
  ASSERT_NE(s.strategies.end(), std::find(s.strategies.begin(), s.strategies.end(), "homologation"));
  EXPECT_EQ("homologation", s.strategy);

  // Unknown names are refused with the brain's reason; a registered one switches, and back.
  r = model.switchStrategy("no_such_strategy");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(std::string::npos, r.message.find("unknown")) << r.message;
  // match runs match2009: its state machine's root is /MATCH2009, not /MATCH.
  r = model.switchStrategy("match");
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(waitFor([&] { s = model.snapshot(now()); return s.strategy == "match"; }, 10.0)) << describe(s);
  EXPECT_TRUE(waitFor([&] { s = model.snapshot(now()); return s.active_path.rfind("/MATCH2009", 0) == 0; }, 10.0))
      << describe(s);
  r = model.switchStrategy("homologation");
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(waitFor([&] { s = model.snapshot(now()); return s.strategy == "homologation"; }, 10.0)) << describe(s);
  // The strategy's root container is introspected: an active path under it.
  EXPECT_TRUE(waitFor([&] { s = model.snapshot(now()); return s.active_path.rfind("/HOMOLOGATION", 0) == 0; }, 10.0))
      << describe(s);

  // The start: the simulated cord (/sim/set_switch exists here), and the match runs.
  ASSERT_TRUE(waitFor([&] { return model.snapshot(now()).ready; }, 30.0)) << describe(model.snapshot(now()));
  r = model.startMatch();
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_NE(std::string::npos, r.message.find("cord")) << r.message;
  ASSERT_TRUE(waitFor([&] { s = model.snapshot(now()); return s.state == "running"; }, 10.0)) << describe(s);

  // The clock counts down, also between two status messages.
  const Snapshot first = model.snapshot(now());
  ros::WallDuration(1.0).sleep();
  const Snapshot second = model.snapshot(now());
  EXPECT_LT(second.remaining, first.remaining - 0.3) << first.clock << " then " << second.clock;
  EXPECT_NE(first.clock, second.clock);
  EXPECT_GT(second.remaining, 0.0);
  const ros::Time t = now();
  EXPECT_LT(model.snapshot(t + ros::Duration(0.1)).remaining, model.snapshot(t).remaining);  // no message needed

  // Running: the active path goes below the root; the score is the simulator's.
  EXPECT_TRUE(waitFor([&] { s = model.snapshot(now()); return s.active_path.size() > std::string("/HOMOLOGATION").size(); }, 10.0))
      << describe(s);
  EXPECT_TRUE(waitFor([&] { s = model.snapshot(now()); return s.have_score; }, 10.0));
  EXPECT_NE("\xe2\x80\x94", s.score);

  // Diagnostics: devices, worst first.
  ASSERT_TRUE(waitFor([&] { s = model.snapshot(now()); return s.devices.size() >= 3; }, 10.0)) << s.devices.size();
  for (size_t i = 1; i < s.devices.size(); ++i) EXPECT_GE(s.devices[i - 1].level, s.devices[i].level) << i;

  // Emergency: HAL latches /effectors/deactivated true.
  ros::NodeHandle nh;
  std::atomic<bool> deactivated(false);
  ros::Subscriber sub = nh.subscribe<std_msgs::Bool>("/effectors/deactivated", 1,
                                                     [&](const std_msgs::Bool::ConstPtr& m) { deactivated = m->data; });
  r = model.emergencyStop();
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_TRUE(waitFor([&] { return deactivated.load(); }, 10.0));
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_match_panel");
  ros::AsyncSpinner spinner(1);  // the test's own subscription (the model spins its own queue)
  spinner.start();
  return RUN_ALL_TESTS();
}
