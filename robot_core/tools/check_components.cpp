// A config's component blocks checked with no master, no bus and no process started: every block
// under NAMESPACE whose value is a dictionary with a `type` must name a plugin PACKAGE declares (as
// ComponentHost::loadFromParameters will ask when hcl_node or hal_node starts), and that plugin's
// own parameter reader (robot_core/configurable_component.h) runs over the block: a missing,
// mistyped or out-of-range value, and every key the reader never asked for, is an error.
//   check_components CONFIG.yaml NAMESPACE PACKAGE KIND     (e.g. merged.yaml hcl hcl_drivers board)
// One line per error on stderr ("parameter /hcl/motor_board/type = 'Motorboard': unknown board
// type; allowed values: ...", "parameter /hcl/io/adress = 32: not a parameter of board type
// MCP23016 (it reads: address, bus, ...)"), exit 1; nothing and exit 0 when the blocks are good.
//   check_components CONFIG.yaml NAMESPACE PACKAGE KIND --describe
// also prints, for each good block, what its reader declared of each parameter (the generated
// parameter tables, make docs): "TYPE<tab>name<tab>type<tab>required|optional<tab>default<tab>rule<tab>meaning",
// and the host's own values (robot_core/host_settings.h) as TYPE "(host)".
#include <nodelet/nodelet.h>
#include <pluginlib/class_loader.hpp>

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "robot_core/component_host.h"
#include "robot_core/configurable_component.h"
#include "robot_core/describe_line.h"
#include "robot_core/host_settings.h"
#include "robot_core/params.h"
#include "robot_core/robot_geometry.h"
#include "robot_core/unknown_keys.h"

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::ostringstream s;
  for (std::size_t i = 0; i < names.size(); ++i) s << (i ? ", " : "") << names[i];
  return s.str();
}

// The errors of one block: its plugin's reader over it, then the keys nobody asked for.
int checkBlock(pluginlib::ClassLoader<nodelet::Nodelet>& plugins, const std::string& package,
               const std::string& type, const std::string& kind, const robot_core::Params& block,
               const robot_core::RobotGeometry& robot, bool describe) {
  boost::shared_ptr<nodelet::Nodelet> plugin;
  try {
    plugin = plugins.createInstance(package + "/" + type);
  } catch (const pluginlib::PluginlibException& e) {
    std::fprintf(stderr, "%s %s: its plugin cannot be loaded: %s\n", kind.c_str(), block.ns().c_str(), e.what());
    return 1;
  }
  const auto* reader = dynamic_cast<const robot_core::ConfigurableComponent*>(plugin.get());
  if (!reader) return 0;  // a plugin without its own reader: its node checks it at start
  try {
    reader->readConfig(block, robot);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  int errors = 0;
  for (const std::string& line : robot_core::unknownKeys(block, kind + " type " + type)) {
    std::fprintf(stderr, "%s\n", line.c_str());
    ++errors;
  }
  if (describe && !errors)
    for (const auto& [name, d] : block.declarations())
      std::printf("%s\n", robot_core::describeLine(type, name, d).c_str());
  return errors;
}

}  // namespace

int main(int argc, char** argv) {
  const bool describe = argc == 6 && std::string(argv[5]) == "--describe";
  if (argc != 5 && !describe) {
    std::fprintf(stderr, "usage: check_components CONFIG.yaml NAMESPACE PACKAGE KIND [--describe]\n");
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
  robot_core::RobotGeometry robot;  // the description (/robot) some readers take values from
  try {
    robot = robot_core::RobotGeometry::read(all["robot"]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  int errors = 0;
  try {  // the host's own values
    robot_core::HostSettings::read(host, kind);
    if (describe)
      for (const auto& [name, d] : host.declarations())
        if (name.find('/') == std::string::npos) std::printf("%s\n", robot_core::describeLine("(host)", name, d).c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    ++errors;
  }
  const std::vector<std::string> types = robot_core::ComponentHost::declaredTypes(package);
  pluginlib::ClassLoader<nodelet::Nodelet> plugins("nodelet", "nodelet::Nodelet");
  for (const std::string& key : host.keys()) {
    const robot_core::Params block = host[key];
    if (!block.has("type")) continue;  // a host setting (num_worker_threads), not a component
    // the host's own two keys (ComponentHost::loadFromParameters reads them so)
    block.describe("enabled", "false: the host does not load this block (its settings stay for when it is enabled)");
    if (!block.optionalBool("enabled", true)) continue;
    block.describe("type", "the " + kind + " type, a plugin of " + package + " (a section of this table)");
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
                   block.qualified("type").c_str(), type.c_str(), kind.c_str(), joined(types).c_str());
      ++errors;
      continue;
    }
    errors += checkBlock(plugins, package, type, kind, block, robot, describe);
  }
  return errors ? 1 : 0;
}
