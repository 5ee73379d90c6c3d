// A component (a board, a device) whose parameter reader runs on its own: in its node at start,
// and over a config file's block with no master and no bus (check_components, so check_config).
// BoardNodelet and DeviceNodelet implement it; the checker finds it on the loaded plugin.
#pragma once

#include "robot_core/params.h"
#include "robot_core/robot_geometry.h"

namespace robot_core {

class ConfigurableComponent {
 public:
  virtual ~ConfigurableComponent();

  // Read every parameter of the component from `params`, its private namespace, with the
  // robot's description `robot` (/robot) for what it takes from there: a bad value throws
  // ParameterError (one line, the parameter and the value). Opens nothing, starts nothing.
  virtual void readConfig(const Params& params, const RobotGeometry& robot) const = 0;
};

}  // namespace robot_core
