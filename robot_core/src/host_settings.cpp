#include "robot_core/host_settings.h"

namespace robot_core {

HostSettings HostSettings::read(const Params& host, const std::string& kind) {
  HostSettings s;
  host.describe("realtime_priority", "SCHED_FIFO priority (1..99) of every " + kind +
                                         "'s loop, with memory locked, where the process may (robot_core/realtime.h); "
                                         "0: normal scheduling");
  s.realtime_priority = host.optionalInt("realtime_priority", 0);
  host.requireInRange("realtime_priority", s.realtime_priority, 0, 99);
  host.describe("only", "load just these " + kind + " blocks (a replay through one of them); empty: every block");
  s.only = host.optionalStringList("only");
  for (const std::string& name : s.only)
    if (!host.has(name + "/type"))
      host.check("only", "'" + name + "' is not a configured " + kind + " (a block with a type under " + host.ns() + ")");
  return s;
}

}  // namespace robot_core
