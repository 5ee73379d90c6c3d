// The simulator's parameters read by its own readers, with no master, no world built and no
// channel opened: the node's own (SimulatorSettings), its world (parseWorldConfig: /sim/world
// against /table and /robot) and each emulator's (Firmware::configure over sim/firmware/<name>,
// with the keys it never asked for) of a config file.
//   check_sim_config CONFIG.yaml [--describe]  (the robot's config with its sim overlay and overlays merged)
// Each error on one line on stderr (the parameter, the value, what is allowed), exit 1; nothing
// and exit 0 when they are accepted or the file has no sim block. With --describe, what the
// readers declared of each parameter, a line each on stdout (the generated parameter tables, make
// docs): "simulator|world|table|robot|firmware:TYPE<tab>name<tab>type<tab>required|optional<tab>default<tab>rule<tab>meaning".
#include <cstdio>
#include <string>

#include <robot_core/describe_line.h>
#include <robot_core/params.h>

#include "robot_sim/firmware/firmware_check.h"
#include "robot_sim/world/config.h"
#include "robot_sim/world/simulator_settings.h"

namespace {
void print(const std::string& table, const std::string& name, const robot_core::ParameterDeclaration& d) {
  std::printf("%s\n", robot_core::describeLine(table, name, d).c_str());
}
}  // namespace

int main(int argc, char** argv) {
  const bool describe = argc == 3 && std::string(argv[2]) == "--describe";
  if (argc != 2 && !describe) {
    std::fprintf(stderr, "usage: check_sim_config CONFIG.yaml [--describe]\n");
    return 2;
  }
  robot_core::Params all;
  try {
    all = robot_core::Params::fromYamlFile(argv[1]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  int errors = 0;
  if (all.has("sim/world")) {
    try {
      const robot_core::Params sim = all["sim"];
      robot_sim::SimulatorSettings::read(sim);
      const robot_core::Params world = all["sim/world"], table = all["table"], robot = all["robot"];
      robot_sim::parseWorldConfig(world, table, robot);
      if (describe) {
        for (const auto& [name, d] : sim.declarations())
          if (name.rfind("world/", 0) != 0 && name.rfind("firmware/", 0) != 0) print("simulator", name, d);
        for (const auto& [name, d] : world.declarations()) print("world", name, d);
        for (const auto& [name, d] : table.declarations()) print("table", name, d);
        // the description's values the simulated robot takes (its links are robot_urdf's table, links/<name>)
        for (const auto& [name, d] : robot.declarations())
          if (name.rfind("links/", 0) != 0) print("robot", name, d);
      }
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s\n", e.what());
      ++errors;
    }
  }
  if (all.has("sim/firmware")) {  // every emulator's block, also when the world refused a value
    const auto declared = [describe](const std::string& type, const robot_core::Params& block) {
      if (!describe) return;
      for (const auto& [name, d] : block.declarations()) print("firmware:" + type, name, d);
    };
    for (const std::string& line : robot_sim::checkEmulatorBlocks(all["sim/firmware"], declared)) {
      std::fprintf(stderr, "%s\n", line.c_str());
      ++errors;
    }
  }
  return errors ? 1 : 0;
}
