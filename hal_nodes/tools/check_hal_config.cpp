// The HAL's device blocks read by the devices' own readers, with no master and no device started:
// every enabled `hal:` block of type Driver (its controllers, recovery and device settings) and
// Localization (filter, inputs, outputs, against /table).
//   check_hal_config CONFIG.yaml     (the robot's config with its overlays merged, as the launch loads it)
// One line per error on stderr (the reader's ParameterError: the parameter, the value, what is
// allowed), exit 1; nothing and exit 0 when every reader accepts its block.
#include <cstdio>
#include <functional>
#include <string>

#include <robot_core/params.h>

#include "../src/devices/localization/localization_config.h"
#include "hal_nodes/driver/driver_config.h"
#include "hal_nodes/driver/recovery.h"

using robot_core::Params;

namespace {

// Runs one reader; its error, if any, on one line.
bool accepted(const std::function<void()>& read) {
  try {
    read();
    return true;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return false;
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: check_hal_config CONFIG.yaml\n");
    return 2;
  }
  Params all;
  if (!accepted([&] { all = Params::fromYamlFile(argv[1]); })) return 1;
  const Params hal = all["hal"], table = all["table"];
  robot_core::RobotGeometry robot;  // the description (/robot) the driver and the localization take values from
  if (!accepted([&] { robot = robot_core::RobotGeometry::read(all["robot"]); })) return 1;
  int errors = 0;
  for (const std::string& key : hal.keys()) {
    const Params device = hal[key];
    if (!device.has("type") || !device.optionalBool("enabled", true)) continue;
    const std::string type = device.optionalString("type", "");
    namespace d = hal_nodes::driver;
    if (type == "Driver") {
      d::AutopilotConfig autopilot;
      if (accepted([&] { autopilot = d::readAutopilotConfig(device, robot); }))
        errors += !accepted([&] { d::readAvoidanceConfig(device, autopilot, robot); });
      else
        ++errors;
      errors += !accepted([&] { d::readPathFollowerConfig(device); });
      errors += !accepted([&] { d::readRecoveryConfig(device); });
      errors += !accepted([&] { d::readDriverDeviceConfig(device); });
    } else if (type == "Localization") {
      errors += !accepted([&] { hal_nodes::localization::readLocalizationConfig(device, table, robot); });
    }
  }
  return errors ? 1 : 0;
}
