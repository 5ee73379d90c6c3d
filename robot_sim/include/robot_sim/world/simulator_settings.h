// The simulator node's own parameters (its private namespace, /sim/...), read by one reader with
// no master: by the node at start and by check_sim_config (the parameter table, make docs).
// The world (~world) and the emulators (~firmware) have readers of their own.
#pragma once

#include <string>
#include <vector>

#include <robot_core/params.h>

#include "robot_sim/world/fault_schedule.h"

namespace robot_sim {

struct SimulatorSettings {
  int seed = 1;
  double real_time_factor = 1.0;  // 0: as fast as the machine goes (machine_pace.h)
  bool paused = false;
  double truth_rate = 50.0;     // [sim Hz]
  double elements_rate = 10.0;  // [sim Hz]
  double match_rate = 10.0;     // [sim Hz]
  double marker_rate = 5.0;     // [sim Hz]
  double clock_max_rate = 1000.0;  // [wall Hz]
  int realtime_priority = 0;
  bool firmware_enabled = true;
  std::vector<FaultEntry> faults;  // scripted at start (their kinds and targets are checked by the node)

  // Throws robot_core::ParameterError naming the parameter on a bad value.
  static SimulatorSettings read(const robot_core::Params& sim);
  // What real_time_factor allows (also the /sim/set_real_time_factor service's rule).
  static bool validFactor(double factor);
  static constexpr const char* kFactorRule = "must be >= 0 (0: as fast as the machine goes)";
};

}  // namespace robot_sim
