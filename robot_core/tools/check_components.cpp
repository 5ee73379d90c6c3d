// A config's component blocks checked with no master and no process started: every block under
// NAMESPACE whose value is a dictionary with a `type` must name a plugin PACKAGE declares, as
// ComponentHost::loadFromParameters will ask when hcl_node or hal_node starts.
//   check_components CONFIG.yaml NAMESPACE PACKAGE KIND     (e.g. merged.yaml hcl hcl_drivers board)
// One line per error on stderr ("parameter /hcl/motor_board/type = 'Motorboard': unknown board
// type; allowed values: ..."), exit 1; nothing and exit 0 when every type is known.
#include <algorithm>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "robot_core/component_host.h"
#include "robot_core/params.h"

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: check_components CONFIG.yaml NAMESPACE PACKAGE KIND\n");
    return 2;
  }
  const std::string ns = argv[2], package = argv[3], kind = argv[4];
  robot_core::Params all;
  try {
    all = robot_core::Params::fromYamlFile(argv[1]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  if (!all.has(ns)) return 0;  // nothing of this kind configured: the host itself says so at start
  const robot_core::Params host = all[ns];
  const std::vector<std::string> types = robot_core::ComponentHost::declaredTypes(package);
  std::ostringstream allowed;
  for (std::size_t i = 0; i < types.size(); ++i) allowed << (i ? ", " : "") << types[i];
  int errors = 0;
  for (const std::string& key : host.keys()) {
    const robot_core::Params block = host[key];
    if (!block.has("type")) continue;  // a host setting (num_worker_threads), not a component
    if (block.has("enabled") && !block.optionalBool("enabled", true)) continue;
    std::string type;
    try {
      type = block.requireString("type");
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s\n", e.what());
      ++errors;
      continue;
    }
    if (std::find(types.begin(), types.end(), type) == types.end()) {
      std::fprintf(stderr, "parameter %s = '%s': unknown %s type; allowed values: %s\n",
                   block.qualified("type").c_str(), type.c_str(), kind.c_str(), allowed.str().c_str());
      ++errors;
    }
  }
  return errors ? 1 : 0;
}
