// Benchmark of the world step: how many times faster than real time the world runs with our
// robot, the opponent and every configured sensor read at its usual rate.
//   sim_bench <params.xml> [simulated seconds]
// params.xml: the robot's parameter tree (/table and /sim/world) as one XML-RPC <value>,
// written by scripts/bench/sim.sh from the YAML config.
#include <xmlrpcpp/XmlRpcValue.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "robot_sim/world/sim_world.h"

using robot_sim::SimWorld;

namespace {
double runWorld(const robot_sim::WorldConfig& config, double seconds, bool sensors, long* reads) {
  SimWorld world(config, 1);
  const auto& r = config.robot;
  std::string left, right;
  for (const auto& kv : r.motors) {
    if (kv.second.drive == "left") left = kv.first;
    if (kv.second.drive == "right") right = kv.first;
  }
  const long steps = static_cast<long>(seconds / config.dt);
  // Sensor periods in steps: encoders and motors 100 Hz, rangers and compass 20 Hz, switches
  // 50 Hz, beacons 50 Hz, camera snapshot 10 Hz, battery 1 Hz.
  auto every = [&](double hz) { return std::max(1L, static_cast<long>(std::lround(1.0 / (hz * config.dt)))); };
  const long p100 = every(100), p50 = every(50), p20 = every(20), p10 = every(10), p1 = every(1);
  volatile double sink = 0.0;
  *reads = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (long k = 0; k < steps; ++k) {
    const double t = k * config.dt;
    if (k % p100 == 0) {
      world.setMotorCommand(left, 0.5 + 0.4 * std::sin(0.9 * t));
      world.setMotorCommand(right, 0.5 + 0.4 * std::cos(0.6 * t));
    }
    world.step();
    if (!sensors) continue;
    if (k % p100 == 0) {
      for (const auto& kv : r.encoders) sink = sink + static_cast<double>(world.encoderTicks(kv.first));
      for (const auto& kv : r.motors) sink = sink + world.motorCurrent(kv.first);
      for (const auto& kv : r.servos) sink = sink + world.servoPosition(kv.first);
      for (const auto& kv : r.steppers) sink = sink + static_cast<double>(world.stepperPosition(kv.first));
      *reads += static_cast<long>(r.encoders.size() + r.motors.size() + r.servos.size() + r.steppers.size());
    }
    if (k % p50 == 0) {
      for (const auto& kv : r.switches) sink = sink + world.switchClosed(kv.first);
      sink = sink + static_cast<double>(world.takeBeaconMeasurements().size());
      *reads += static_cast<long>(r.switches.size()) + 1;
    }
    if (k % p20 == 0) {
      for (const auto& kv : r.rangers) sink = sink + std::min(9.0, world.measureRange(kv.first));
      sink = sink + world.measureCompassDeg();
      *reads += static_cast<long>(r.rangers.size()) + 1;
    }
    if (k % p10 == 0) {
      sink = sink + world.snapshot().robot.x;
      ++*reads;
    }
    if (k % p1 == 0) {
      sink = sink + world.batteryVoltage();
      ++*reads;
    }
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return seconds / wall;
}
}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: sim_bench <params.xml> [simulated seconds]\n");
    return 2;
  }
  std::ifstream in(argv[1]);
  std::stringstream buf;
  buf << in.rdbuf();
  const std::string xml = buf.str();
  int offset = static_cast<int>(xml.find("<value>"));
  if (offset < 0) {
    std::fprintf(stderr, "sim_bench: no <value> in %s\n", argv[1]);
    return 2;
  }
  XmlRpc::XmlRpcValue root(xml, &offset);
  const double seconds = argc > 2 ? std::atof(argv[2]) : 100.0;
  try {
    XmlRpc::XmlRpcValue world, robot, table = root["table"];
    if (root.hasMember("sim") && root["sim"].hasMember("world")) world = root["sim"]["world"];
    if (root.hasMember("robot")) robot = root["robot"];
    const auto config = robot_sim::parseWorldConfig(world, "/sim/world", table, "/table", robot, "/robot");
    long reads = 0;
    const double step_only = runWorld(config, seconds, false, &reads);
    const double with_sensors = runWorld(config, seconds, true, &reads);
    std::printf("  world step alone:            %8.1fx real time (dt %.4f s, %zu elements, opponent %s)\n",
                step_only, config.dt, config.table.elements.size(), config.opponent.enabled ? "on" : "off");
    std::printf("  step + all sensors/actuators: %8.1fx real time (%.0f reads per simulated second)\n",
                with_sensors, reads / seconds);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sim_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
