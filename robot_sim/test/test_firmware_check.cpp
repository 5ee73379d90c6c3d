// The emulators' own readers over a config with no master, no world and no channel
// (checkEmulatorBlocks: check_sim_config, so check_config and the parameter tables).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "robot_sim/firmware/firmware_check.h"

namespace {

std::string writeYaml(const std::string& text) {
  char name[] = "/tmp/test_firmware_check_XXXXXX";
  const int fd = mkstemp(name);
  close(fd);
  std::ofstream(name) << text;
  return name;
}

bool contains(const std::vector<std::string>& lines, const std::string& text) {
  for (const auto& l : lines)
    if (l.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST(FirmwareCheck, EveryShippedEmulatorBlockIsReadAndEachParameterHasAMeaning) {
  for (const std::string robot : {"eurobot2009", "logion", "skeleton"}) {
    const auto firmware = robot_core::Params::fromYamlFile(std::string(ROBOT_CONFIG_DIR) + "/" + robot + ".sim.yaml",
                                                           "sim/firmware");
    int blocks = 0;
    const auto errors = robot_sim::checkEmulatorBlocks(firmware, [&](const std::string& type, const robot_core::Params& b) {
      ++blocks;
      for (const auto& [name, d] : b.declarations()) EXPECT_FALSE(d.meaning.empty()) << type << " " << name;
    });
    EXPECT_TRUE(errors.empty()) << robot << ": " << errors.front();
    EXPECT_GT(blocks, 0) << robot;
  }
}

TEST(FirmwareCheck, AnUnknownKeyABadValueAndAnUnknownTypeAreEachOneLine) {
  const std::string f = writeYaml(
      "sim:\n"
      "  firmware:\n"
      "    motor_board: {type: MotorBoard, bus: \"udp://127.0.0.1:27000\", node_id: 10, motors: [left], moters: [x]}\n"
      "    compass: {type: CMPS03, bus: \"sim:///tmp/x/i2c-1\", address: 0x05}\n"
      "    camera: {type: Camra, port: 27230}\n"
      "    off: {type: Camra, enabled: false}\n"
      "    not_an_emulator: 3\n");
  const auto errors = robot_sim::checkEmulatorBlocks(robot_core::Params::fromYamlFile(f, "sim/firmware"));
  std::remove(f.c_str());
  ASSERT_EQ(errors.size(), 3u) << (errors.empty() ? "" : errors.front());
  EXPECT_TRUE(contains(errors, "/sim/firmware/motor_board/moters = a list of 1: not a parameter of emulator type MotorBoard"));
  EXPECT_TRUE(contains(errors, "/sim/firmware/compass/address = 5: must be in"));
  EXPECT_TRUE(contains(errors, "/sim/firmware/camera/type = 'Camra': unknown emulator type; allowed values: "));
}

TEST(FirmwareCheck, ConfiguringAnEmulatorTouchesNoChannel) {
  // a check beside a running simulation must not remove its FIFO or its pty link
  const std::string dir = "/tmp/test_firmware_check_" + std::to_string(getpid());
  ::mkdir(dir.c_str(), 0777);
  const std::string fifo = dir + "/js0", tty = dir + "/beacons.tty";
  std::ofstream(fifo) << "";
  std::ofstream(tty) << "";
  const std::string f = writeYaml("sim:\n  firmware:\n    joystick: {type: Joystick, device: " + fifo +
                                  "}\n    beacons: {type: BeaconReceiver, port: " + tty + "}\n");
  const auto errors = robot_sim::checkEmulatorBlocks(robot_core::Params::fromYamlFile(f, "sim/firmware"));
  std::remove(f.c_str());
  EXPECT_TRUE(errors.empty()) << errors.front();
  EXPECT_EQ(::access(fifo.c_str(), F_OK), 0) << "the joystick's configure() or destructor removed its device";
  EXPECT_EQ(::access(tty.c_str(), F_OK), 0) << "the beacon receiver's configure() or destructor removed its link";
  std::remove(fifo.c_str());
  std::remove(tty.c_str());
  ::rmdir(dir.c_str());
}
