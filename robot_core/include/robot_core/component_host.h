// A nodelet manager process that loads the components (boards or devices) listed in its
// private parameters: every key whose value is a dictionary with a `type` is one component,
// loaded as nodelet "<package>/<type>" named "<this node>/<key>". `enabled: false` skips it.
// Used by hcl_node (boards) and hal_nodes' hal_node (devices), so a robot is described by
// its config alone: adding a board is one config block, not a launch-file edit.
// Once loaded, `~status_names` lists the /diagnostics status of each component ("hcl/motor_board:
// board"): the brain's readiness waits for every one of them, not only for those heard so far.
#pragma once

#include <nodelet/loader.h>
#include <ros/ros.h>

#include <memory>
#include <string>
#include <vector>

namespace robot_core {

class ComponentHost {
 public:
  // `package`: plugin name prefix ("hcl_drivers"); `kind`: "board" or "device", for messages.
  ComponentHost(std::string package, std::string kind);

  // Load every configured component (only those named in `~only` when it is set). On a bad
  // configuration prints one line naming the parameter and the allowed values and returns false
  // (the caller exits non-zero).
  bool loadFromParameters(const ros::NodeHandle& pnh);

  // Plugin types this package declares (without the package prefix), sorted.
  std::vector<std::string> availableTypes() const { return declaredTypes(package_); }
  // The same for any package, with no master and no host (check_components).
  static std::vector<std::string> declaredTypes(const std::string& package);
  const std::vector<std::string>& loaded() const { return loaded_; }

 private:
  std::string package_;
  std::string kind_;
  std::unique_ptr<nodelet::Loader> loader_;
  std::vector<std::string> loaded_;
};

}  // namespace robot_core
