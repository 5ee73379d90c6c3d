#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <string>

#include <unistd.h>

#include "robot_core/robot_geometry.h"
#include "yaml_file.h"

using robot_core::ParameterError;
using robot_core::Params;
using robot_core::RobotGeometry;

namespace {

std::string errorOf(const std::function<void()>& read) {
  try {
    read();
  } catch (const ParameterError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(RobotGeometry, ReadsTheShippedDescriptions) {
  for (const char* robot : {"eurobot2009", "logion"}) {
    const std::string file = std::string(ROBOT_CONFIG_DIR) + "/" + robot + ".yaml";
    const RobotGeometry g = RobotGeometry::read(Params::fromYamlFile(file, "robot"));
    ASSERT_TRUE(g.radius && g.track_width && g.wheel_radius) << robot;
    EXPECT_GT(*g.track_width, 2.0 * *g.wheel_radius) << robot;
    EXPECT_GT(*g.radius, *g.track_width / 2.0) << robot;
  }
}

TEST(RobotGeometry, ABlockTakesTheDescriptionsValueUnlessItSetsItsOwn) {
  const std::string f = writeYaml(
      "robot: {radius: 0.16, track_width: 0.25, encoder_ticks_per_rev: 512}\n"
      "hal:\n"
      "  drive: {rate: 50}\n"
      "  rig: {track_width: 0.3}\n"
      "  bad: {track_width: -0.3}\n");
  const RobotGeometry g = RobotGeometry::read(Params::fromYamlFile(f, "robot"));
  EXPECT_FALSE(g.wheel_radius);  // left out of the description: empty, not a default
  EXPECT_DOUBLE_EQ(*g.encoder_ticks_per_rev, 512.0);
  const Params drive = Params::fromYamlFile(f, "hal/drive");
  EXPECT_DOUBLE_EQ(RobotGeometry::blockOrDescribed(drive, "track_width", g.track_width, "track_width", "[m] track"), 0.25);
  EXPECT_EQ(drive.declarations().at("track_width").fallback, "/robot/track_width");  // the table's default column
  const Params rig = Params::fromYamlFile(f, "hal/rig");
  EXPECT_DOUBLE_EQ(RobotGeometry::blockOrDescribed(rig, "track_width", g.track_width, "track_width", "[m] track"), 0.3);
  EXPECT_EQ(errorOf([&] {
              RobotGeometry::blockOrDescribed(Params::fromYamlFile(f, "hal/bad"), "track_width", g.track_width,
                                              "track_width", "[m] track");
            }),
            "parameter /hal/bad/track_width = -0.3: must be > 0");
  // Neither the block nor the description: the error names both; a reader's own fallback instead.
  EXPECT_EQ(errorOf([&] { RobotGeometry::blockOrDescribed(drive, "wheel_radius", g.wheel_radius, "wheel_radius", "[m]"); }),
            "parameter /hal/drive/wheel_radius: not set, and the robot's description has no /robot/wheel_radius");
  EXPECT_DOUBLE_EQ(RobotGeometry::blockOrDescribed(drive, "wheel_radius", g.wheel_radius, "wheel_radius", "[m]", 0.03),
                   0.03);
  std::remove(f.c_str());
}

TEST(RobotGeometry, RefusesABadDescription) {
  const std::string f = writeYaml("robot: {radius: 0, track_width: wide}\n");
  EXPECT_EQ(errorOf([&] { RobotGeometry::read(Params::fromYamlFile(f, "robot")); }),
            "parameter /robot/radius = 0: must be > 0");
  const RobotGeometry none = RobotGeometry::read(Params());  // no description at all: every value empty
  EXPECT_FALSE(none.radius || none.track_width || none.wheel_radius || none.encoder_ticks_per_rev);
  std::remove(f.c_str());
}
