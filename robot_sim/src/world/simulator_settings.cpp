// Each read is described beside it (the table: robot_sim/PARAMETERS.md, make docs).
#include "robot_sim/world/simulator_settings.h"

#include <cmath>
#include <utility>

namespace robot_sim {

bool SimulatorSettings::validFactor(double factor) { return factor >= 0.0 && std::isfinite(factor); }

SimulatorSettings SimulatorSettings::read(const robot_core::Params& sim) {
  SimulatorSettings s;
  s.seed = sim.optionalInt("seed", s.seed);
  if (s.seed < 0) sim.check("seed", "must be an integer >= 0");
  sim.describe("seed", "(>= 0) the world's random seed: same seed and same timed commands, same trajectory");
  s.real_time_factor = sim.optionalDouble("real_time_factor", s.real_time_factor);
  if (!validFactor(s.real_time_factor)) sim.check("real_time_factor", kFactorRule);
  sim.describe("real_time_factor", "(>= 0) simulated seconds per wall second; 0: as fast as the machine goes "
                                   "(the factor that keeps it just short of saturation)");
  s.paused = sim.optionalBool("paused", s.paused);
  sim.describe("paused", "start frozen at t = 0 (a test scripts the world, then resumes it: /sim/pause)");
  const std::pair<const char*, double*> rates[] = {
      {"truth_rate", &s.truth_rate}, {"elements_rate", &s.elements_rate}, {"match_rate", &s.match_rate},
      {"marker_rate", &s.marker_rate}};
  const char* what[] = {"/sim/ground_truth and /sim/opponent", "/sim/elements", "/sim/match and /sim/score",
                        "/sim/markers"};
  for (int i = 0; i < 4; ++i) {
    *rates[i].second = sim.optionalDouble(rates[i].first, *rates[i].second);
    if (!(*rates[i].second > 0.0) || *rates[i].second > 2000.0) sim.check(rates[i].first, "must be in (0, 2000] Hz");
    sim.describe(rates[i].first, std::string("[Hz, simulated] (0, 2000] ") + what[i]);
  }
  s.clock_max_rate = sim.optionalDouble("clock_max_rate", s.clock_max_rate);
  if (!(s.clock_max_rate >= 10.0)) sim.check("clock_max_rate", "must be >= 10 Hz");
  sim.describe("clock_max_rate", "[Hz, wall] (>= 10) /clock is published at most this often");
  const double priority = sim.optionalDouble("realtime_priority", s.realtime_priority);
  if (priority != std::floor(priority) || priority < 0 || priority > 99)
    sim.check("realtime_priority", "must be an integer 0..99 (0: normal scheduling)");
  s.realtime_priority = static_cast<int>(priority);
  sim.describe("realtime_priority", "(integer 0 .. 99) SCHED_FIFO priority of the emulators' and the simulated bus's threads, "
                                    "answering like hardware (0: normal scheduling; the world's thread stays normal)");
  s.firmware_enabled = sim.optionalBool("firmware_enabled", s.firmware_enabled);
  sim.describe("firmware_enabled", "false: the world alone, no emulators (world tests)");
  sim.describe("faults", "faults scripted at start: [{kind, target, start [s], duration [s] (0: until cleared), "
                         "magnitude (0: the kind's default)}] (the kinds: robot_sim/README.md)");
  for (const robot_core::Params& f : sim.items("faults")) {
    FaultEntry e;
    e.kind = f.requireString("kind");
    e.target = f.optionalString("target", "");
    e.start = f.optionalDouble("start", 0.0);
    const double duration = f.optionalDouble("duration", 0.0);
    e.end = duration > 0.0 ? e.start + duration : 0.0;
    e.magnitude = f.optionalDouble("magnitude", 0.0);
    s.faults.push_back(e);
  }
  return s;
}

}  // namespace robot_sim
