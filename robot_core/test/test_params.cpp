#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include <unistd.h>

#include "robot_core/host_settings.h"
#include "robot_core/params.h"
#include "yaml_file.h"

using robot_core::ParameterError;
using robot_core::Params;


TEST(Params, TypesAsRosparamLoadsThem) {
  const std::string f = writeYaml(
      "hal:\n"
      "  driver:\n"
      "    rate: 50\n"
      "    ratio: 0.5\n"
      "    address: 0x60\n"
      "    enabled: true\n"
      "    name: \"0x10\"\n"
      "    mode: stop\n"
      "    limits: {max: 1.0e-1, min: -.inf, text: 1e-1}\n"
      "    list: [1, 2]\n");
  const Params p = Params::fromYamlFile(f, "hal/driver");
  EXPECT_EQ(p.ns(), "/hal/driver");
  EXPECT_DOUBLE_EQ(p.requireDouble("rate"), 50.0);  // an integer where a number is asked for
  EXPECT_EQ(p.requireInt("rate"), 50);
  EXPECT_DOUBLE_EQ(p.requireDouble("ratio"), 0.5);
  EXPECT_EQ(p.requireInt("address"), 0x60);
  EXPECT_TRUE(p.optionalBool("enabled", false));
  EXPECT_EQ(p.requireString("name"), "0x10");  // quoted: a string
  EXPECT_EQ(p.optionalString("mode", "off"), "stop");
  EXPECT_DOUBLE_EQ(p["limits"].requireDouble("max"), 0.1);
  EXPECT_TRUE(std::isinf(p.requireDouble("limits/min")));
  EXPECT_EQ(p["limits"].requireString("text"), "1e-1");  // YAML 1.1: no dot, no number
  EXPECT_EQ(p["limits"].qualified("max"), "/hal/driver/limits/max");
  EXPECT_DOUBLE_EQ(p.optionalDouble("absent", 2.5), 2.5);
  EXPECT_DOUBLE_EQ(p["absent_block"].optionalDouble("x", 1.5), 1.5);
  std::remove(f.c_str());
}

TEST(Params, ErrorsNameTheParameter) {
  const std::string f = writeYaml("b: {rate: fast, n: 2.5, speed: -1}\n");
  const Params p = Params::fromYamlFile(f, "b");
  try {
    p.requireDouble("rate");
    FAIL() << "a string read as a number";
  } catch (const ParameterError& e) {
    EXPECT_STREQ(e.what(), "parameter /b/rate = 'fast' has the wrong type: expected a number");  // the value quoted
  }
  try {
    p.requireInt("n");
    FAIL() << "2.5 read as an integer";
  } catch (const ParameterError& e) {
    EXPECT_STREQ(e.what(), "parameter /b/n = 2.5 has the wrong type: expected an integer");
  }
  try {
    p.requireDouble("missing");
    FAIL();
  } catch (const ParameterError& e) {
    EXPECT_STREQ(e.what(), "missing required parameter /b/missing (a number)");
  }
  try {
    p.requirePositive("speed", p.requireDouble("speed"));
    FAIL();
  } catch (const ParameterError& e) {
    EXPECT_STREQ(e.what(), "parameter /b/speed = -1: must be > 0");
  }
  EXPECT_THROW(Params::fromYamlFile(f, "no/such/block"), ParameterError);
  EXPECT_THROW(Params::fromYamlFile("/no/such/file.yaml"), ParameterError);
  std::remove(f.c_str());
}

TEST(Params, ReadsTheRobotsConfig) {
  for (const char* robot : {"eurobot2009", "logion"}) {
    const Params p = Params::fromYamlFile(std::string(ROBOT_CONFIG_DIR) + "/" + robot + ".yaml", "hal/driver");
    EXPECT_EQ(p.requireString("type"), "Driver") << robot;
    EXPECT_GT(p["limits"].requireDouble("max_wheel_speed"), 0.0) << robot;
  }
}

TEST(Params, BlocksListsAndRows) {
  const std::string f = writeYaml(
      "w:\n"
      "  motors: {left: {max: 1}, right: {max: 2}}\n"
      "  zones: [{name: a}, {name: b}]\n"
      "  start: [0.25, 1.8, 0]\n"
      "  kinds: [red, green]\n"
      "  beacons: [[0, 0], [0, 2.1], [3.0, 1.05]]\n"
      "  flat: 5\n"
      "  bad_rows: [[0, 0], [1]]\n"
      "  bad_blocks: {left: 1}\n");
  const Params w = Params::fromYamlFile(f, "w");
  EXPECT_EQ(w.blockNames("motors"), (std::vector<std::string>{"left", "right"}));
  EXPECT_EQ(w["motors"]["right"].requireInt("max"), 2);
  ASSERT_EQ(w.items("zones").size(), 2u);
  EXPECT_EQ(w.items("zones")[1].requireString("name"), "b");
  EXPECT_EQ(w.items("zones")[1].qualified("name"), "/w/zones[1]/name");
  EXPECT_EQ(w.optionalDoubleList("start", 2, 3).size(), 3u);
  EXPECT_TRUE(w.optionalDoubleList("absent", 2, 3).empty());
  EXPECT_EQ(w.optionalStringList("kinds"), (std::vector<std::string>{"red", "green"}));
  const auto rows = w.optionalDoubleRows("beacons", 2);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_DOUBLE_EQ(rows[2][1], 1.05);
  auto refused = [&](auto read, const std::string& names) {
    try {
      read();
      ADD_FAILURE() << "accepted " << names;
    } catch (const ParameterError& e) {
      EXPECT_NE(std::string(e.what()).find(names), std::string::npos) << e.what();
    }
  };
  refused([&] { w.optionalDoubleList("start", 2, 2); }, "/w/start");
  refused([&] { w.optionalDoubleRows("bad_rows", 2); }, "/w/bad_rows");
  refused([&] { w.blockNames("bad_blocks"); }, "/w/bad_blocks/left");
  refused([&] { w.block("flat"); }, "/w/flat");
  refused([&] { w.items("flat"); }, "/w/flat");
  refused([&] { w.optionalStringList("start"); }, "/w/start[0]");
  std::remove(f.c_str());
}

TEST(Params, RemembersWhatAReaderAskedFor) {
  const std::string f = writeYaml(
      "b:\n"
      "  rate: 10\n"
      "  adress: 0x70\n"
      "  pairs: {left: {ticks: 360, tiks: 1}}\n"
      "  zones: [{name: a}, {name: b, colour: red}]\n"
      "  axes: {left_x: 0, left_y: 1}\n"
      "  start: [0.25, 1.8, 0]\n");
  const Params b = Params::fromYamlFile(f, "b");
  b.requireDouble("rate");
  b.optionalInt("address", 0x70);  // absent: known, not reported
  for (const auto& name : b.blockNames("pairs")) b.block("pairs/" + name).requireInt("ticks");
  for (const auto& zone : b.items("zones")) zone.requireString("name");
  b.optionalIntMap("axes");
  b.optionalDoubleList("start", 3, 3);
  // the values no reader looked at, each with its value: a misspelt key, a key inside a named
  // block and one inside a list of dictionaries
  EXPECT_EQ(b.unasked(), (std::vector<std::string>{"/b/adress = 112", "/b/pairs/left/tiks = 1",
                                                    "/b/zones[1]/colour = 'red'"}));
  // what the reader knows, present or not
  EXPECT_EQ(b.askedKeys(), (std::vector<std::string>{"address", "axes", "pairs", "rate", "start", "zones"}));
  std::remove(f.c_str());
}

TEST(Params, RequiredBlocksIntMapsAndRenamedKeys) {
  const std::string f = writeYaml(
      "d:\n"
      "  empty: {}\n"
      "  axes: {left_x: 0, bad: -1}\n"
      "  max_wheel_speed: 4\n");
  const Params d = Params::fromYamlFile(f, "d");
  EXPECT_THROW(d.requireBlockNames("absent"), ParameterError);
  EXPECT_THROW(d.requireBlockNames("empty"), ParameterError);
  EXPECT_THROW(d.optionalIntMap("axes"), ParameterError);
  EXPECT_TRUE(d.optionalIntMap("absent").empty());
  EXPECT_EQ(d.renamed("plausible_wheel_speed", "max_wheel_speed"), "max_wheel_speed");
  EXPECT_EQ(d.renamed("axes", "old_axes"), "axes");
  EXPECT_EQ(d.optionalStringList("absent", {"x"}), (std::vector<std::string>{"x"}));
  std::remove(f.c_str());
}

TEST(Params, UnusedBlocksAreNotUnknownKeys) {
  const std::string f = writeYaml(
      "d:\n"
      "  beacons: {enabled: false, range_std: 0.02}\n"
      "  typo: 1\n");
  const Params d = Params::fromYamlFile(f, "d");
  if (!d.optionalBool("beacons/enabled", true)) d.unused("beacons");
  EXPECT_EQ(d.unasked(), (std::vector<std::string>{"/d/typo = 1"}));
  std::remove(f.c_str());
}

TEST(HostSettings, ReadsItsOwnValuesBesideTheBlocks) {
  const std::string f = writeYaml(
      "hal:\n"
      "  realtime_priority: 20\n"
      "  only: [odometry]\n"
      "  odometry: {type: Odometry}\n");
  const robot_core::HostSettings s = robot_core::HostSettings::read(Params::fromYamlFile(f, "hal"), "device");
  EXPECT_EQ(s.realtime_priority, 20);
  ASSERT_EQ(s.only.size(), 1u);
  EXPECT_EQ(s.only[0], "odometry");
  const Params host = Params::fromYamlFile(f, "hal");
  robot_core::HostSettings::read(host, "device");
  const auto declared = host.declarations();
  EXPECT_EQ(declared.at("realtime_priority").rule, "0 .. 99");
  EXPECT_FALSE(declared.at("only").meaning.empty());
  std::remove(f.c_str());
}

TEST(HostSettings, RefusesAPriorityOutOfRangeAndAnUnknownBlock) {
  const std::string high = writeYaml("hcl:\n  realtime_priority: 100\n");
  try {
    robot_core::HostSettings::read(Params::fromYamlFile(high, "hcl"), "board");
    FAIL() << "a priority of 100 was accepted";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("/hcl/realtime_priority = 100"), std::string::npos) << e.what();
  }
  const std::string only = writeYaml("hal:\n  only: [odometri]\n  odometry: {type: Odometry}\n");
  try {
    robot_core::HostSettings::read(Params::fromYamlFile(only, "hal"), "device");
    FAIL() << "an unknown block in only was accepted";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("'odometri' is not a configured device"), std::string::npos) << e.what();
  }
  std::remove(high.c_str());
  std::remove(only.c_str());
}
