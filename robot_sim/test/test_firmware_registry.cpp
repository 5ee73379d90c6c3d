#include <gtest/gtest.h>

#include <algorithm>

#include "robot_sim/firmware/firmware_registry.h"

TEST(FirmwareRegistry, ExampleBoardIsRegistered) {
  const auto types = robot_sim::FirmwareRegistry::instance().types();
  EXPECT_NE(std::find(types.begin(), types.end(), "ExampleBoard"), types.end());
  EXPECT_TRUE(robot_sim::FirmwareRegistry::instance().create("ExampleBoard"));
}

TEST(FirmwareRegistry, UnknownTypeGivesNothing) {
  EXPECT_FALSE(robot_sim::FirmwareRegistry::instance().create("no_such_board"));
}
