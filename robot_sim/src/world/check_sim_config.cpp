// The simulator's parameters read by its own readers, with no master and no world built: the
// node's own (SimulatorSettings) and its world (parseWorldConfig: /sim/world against /table and
// /robot) of a config file.
//   check_sim_config CONFIG.yaml [--describe]  (the robot's config with its sim overlay and overlays merged)
// The reader's error on one line on stderr (the parameter, the value, what is allowed), exit 1;
// nothing and exit 0 when they are accepted or the file has no sim/world block. With --describe,
// what the readers declared of each parameter, a line each on stdout (the generated parameter
// tables, make docs): "simulator|world<tab>name<tab>type<tab>required|optional<tab>default<tab>rule<tab>meaning".
#include <cstdio>
#include <string>

#include <robot_core/params.h>

#include "robot_sim/world/config.h"
#include "robot_sim/world/simulator_settings.h"

namespace {
void print(const char* table, const std::string& name, const robot_core::ParameterDeclaration& d) {
  std::printf("%s\t%s\t%s\t%s\t%s\t%s\t%s\n", table, name.c_str(), d.type.c_str(), d.required ? "required" : "optional",
              d.fallback.c_str(), d.rule.c_str(), d.meaning.c_str());
}
}  // namespace

int main(int argc, char** argv) {
  const bool describe = argc == 3 && std::string(argv[2]) == "--describe";
  if (argc != 2 && !describe) {
    std::fprintf(stderr, "usage: check_sim_config CONFIG.yaml [--describe]\n");
    return 2;
  }
  try {
    const robot_core::Params all = robot_core::Params::fromYamlFile(argv[1]);
    if (!all.has("sim/world")) return 0;
    const robot_core::Params sim = all["sim"];
    robot_sim::SimulatorSettings::read(sim);
    const robot_core::Params world = all["sim/world"];
    robot_sim::parseWorldConfig(world, all["table"], all["robot"]);
    if (describe) {
      for (const auto& [name, d] : sim.declarations())
        if (name.rfind("world/", 0) != 0) print("simulator", name, d);
      for (const auto& [name, d] : world.declarations()) print("world", name, d);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
