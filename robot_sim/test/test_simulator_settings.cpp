// The simulator node's own parameters (SimulatorSettings::read), with no master: defaults, the
// rules, the scripted faults, and the one line naming a wrong value.
#include <gtest/gtest.h>

#include <string>

#include <robot_core/params.h>

#include "robot_sim/world/simulator_settings.h"

using robot_sim::SimulatorSettings;

namespace {
robot_core::Params sim(XmlRpc::XmlRpcValue tree) { return robot_core::Params(tree, "/sim"); }

std::string refusal(XmlRpc::XmlRpcValue tree) {
  try {
    SimulatorSettings::read(sim(tree));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(SimulatorSettings, DefaultsWhenNothingIsSet) {
  XmlRpc::XmlRpcValue empty;
  empty["world"]["dt"] = 0.001;  // another reader's block: not this one's business
  const SimulatorSettings s = SimulatorSettings::read(sim(empty));
  EXPECT_EQ(s.seed, 1);
  EXPECT_DOUBLE_EQ(s.real_time_factor, 1.0);
  EXPECT_FALSE(s.paused);
  EXPECT_DOUBLE_EQ(s.truth_rate, 50.0);
  EXPECT_DOUBLE_EQ(s.marker_rate, 5.0);
  EXPECT_EQ(s.realtime_priority, 0);
  EXPECT_TRUE(s.firmware_enabled);
  EXPECT_TRUE(s.faults.empty());
}

TEST(SimulatorSettings, ReadsEveryValueAndTheScriptedFaults) {
  XmlRpc::XmlRpcValue t;
  t["seed"] = 7;
  t["real_time_factor"] = 0.0;
  t["paused"] = true;
  t["elements_rate"] = 20;
  t["realtime_priority"] = 40;
  t["firmware_enabled"] = false;
  t["faults"][0]["kind"] = "wheel_slip";
  t["faults"][0]["start"] = 10.0;
  t["faults"][0]["duration"] = 5.0;
  t["faults"][1]["kind"] = "board_silent";
  t["faults"][1]["target"] = "motor_board";
  const SimulatorSettings s = SimulatorSettings::read(sim(t));
  EXPECT_EQ(s.seed, 7);
  EXPECT_DOUBLE_EQ(s.real_time_factor, 0.0);
  EXPECT_TRUE(s.paused);
  EXPECT_DOUBLE_EQ(s.elements_rate, 20.0);
  EXPECT_EQ(s.realtime_priority, 40);
  EXPECT_FALSE(s.firmware_enabled);
  ASSERT_EQ(s.faults.size(), 2u);
  EXPECT_EQ(s.faults[0].kind, "wheel_slip");
  EXPECT_DOUBLE_EQ(s.faults[0].end, 15.0);
  EXPECT_EQ(s.faults[1].target, "motor_board");
  EXPECT_TRUE(s.faults[1].open());  // no duration: until cleared
}

TEST(SimulatorSettings, AWrongValueIsOneLineNamingIt) {
  const std::pair<std::string, std::string> cases[] = {
      {"seed", "/sim/seed"}, {"real_time_factor", "/sim/real_time_factor"}, {"truth_rate", "/sim/truth_rate"},
      {"clock_max_rate", "/sim/clock_max_rate"}, {"realtime_priority", "/sim/realtime_priority"}};
  const double bad[] = {-1, -0.5, 0.0, 5.0, 100.0};
  for (int i = 0; i < 5; ++i) {
    XmlRpc::XmlRpcValue t;
    t[cases[i].first] = bad[i];
    if (cases[i].first == "seed") t[cases[i].first] = -1;
    const std::string why = refusal(t);
    EXPECT_NE(why.find("parameter " + cases[i].second), std::string::npos) << why;
  }
  XmlRpc::XmlRpcValue wrong_type;
  wrong_type["paused"] = "yes";
  EXPECT_NE(refusal(wrong_type).find("/sim/paused"), std::string::npos);
  XmlRpc::XmlRpcValue no_kind;
  no_kind["faults"][0]["target"] = "motor_board";
  EXPECT_NE(refusal(no_kind).find("/sim/faults[0]/kind"), std::string::npos) << refusal(no_kind);
}

TEST(SimulatorSettings, EveryReadIsDescribed) {
  XmlRpc::XmlRpcValue t;
  t["faults"][0]["kind"] = "wheel_slip";
  const robot_core::Params p = sim(t);
  SimulatorSettings::read(p);
  for (const auto& [name, d] : p.declarations()) {
    if (name.rfind("faults[]/", 0) == 0) continue;  // the item keys: described once, on the list
    EXPECT_FALSE(d.meaning.empty()) << name;
  }
  EXPECT_EQ(p.declarations().count("realtime_priority"), 1u);
}
