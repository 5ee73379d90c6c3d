// The simulator's world read by its own reader (parseWorldConfig), with no master and no world
// built: /sim/world against /table and /robot of a config file.
//   check_sim_config CONFIG.yaml     (the robot's config with its sim overlay and overlays merged)
// The reader's error on one line on stderr (the parameter, the value, what is allowed), exit 1;
// nothing and exit 0 when the world is accepted or the file has no sim/world block.
#include <cstdio>

#include <robot_core/params.h>

#include "robot_sim/world/config.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: check_sim_config CONFIG.yaml\n");
    return 2;
  }
  try {
    const robot_core::Params all = robot_core::Params::fromYamlFile(argv[1]);
    if (!all.has("sim/world")) return 0;
    robot_sim::parseWorldConfig(all["sim/world"], all["table"], all["robot"]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
