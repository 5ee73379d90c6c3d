// A component (a board, a device) whose parameter reader runs on its own: in its node at start,
// and over a config file's block with no master and no bus (check_components, so check_config).
// BoardNodelet and DeviceNodelet implement it; the checker finds it on the loaded plugin.
#pragma once

#include "robot_core/params.h"

namespace robot_core {

class ConfigurableComponent {
 public:
  virtual ~ConfigurableComponent();

  // Read every parameter of the component from `params`, its private namespace: a bad value
  // throws ParameterError (one line, the parameter and the value). Opens nothing, starts nothing.
  virtual void readConfig(const Params& params) const = 0;
};

}  // namespace robot_core
