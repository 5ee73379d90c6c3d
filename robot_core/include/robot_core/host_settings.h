// The component host's own values (hcl_node's `hcl:`, hal_node's `hal:`), beside its component
// blocks: read by ComponentHost::loadFromParameters before any component starts, and by
// check_components for check_config and the parameter tables.
#pragma once

#include <string>
#include <vector>

#include "robot_core/params.h"

namespace robot_core {

struct HostSettings {
  int realtime_priority = 0;      // SCHED_FIFO priority of the components' loops; 0: normal scheduling
  std::vector<std::string> only;  // load just these blocks; empty: all of them

  // `kind`: "board" or "device", for the meanings. Throws ParameterError.
  static HostSettings read(const Params& host, const std::string& kind);
};

}  // namespace robot_core
