// The simulator's drive motors driven by commands recorded on a robot: `make calibrate` replays a
// match's PWM commands through the fitted model and compares the encoder counts with the recording.
//   motor_replay <params.xml> <motor>     stdin: "c T U" (command U in -1..1 from time T on) and
//                                         "q T" (where is the wheel at T), in time order
// stdout: one line per "q": the wheel's turns since the first line. params.xml: the robot's
// parameter tree (/table and /sim/world) as one XML-RPC <value>, as for sim_bench. The motor runs
// free (no contact): the recording's stretches against an obstacle are the caller's to leave out.
#include <xmlrpcpp/XmlRpcValue.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "robot_sim/world/config.h"
#include "robot_sim/world/motor_model.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: motor_replay <params.xml> <motor>\n");
    return 2;
  }
  std::ifstream in(argv[1]);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string xml = buffer.str();
  int offset = static_cast<int>(xml.find("<value>"));
  if (offset < 0) {
    std::fprintf(stderr, "motor_replay: no <value> in %s\n", argv[1]);
    return 2;
  }
  try {
    XmlRpc::XmlRpcValue root(xml, &offset);
    XmlRpc::XmlRpcValue world, robot, table = root["table"];
    if (root.hasMember("sim") && root["sim"].hasMember("world")) world = root["sim"]["world"];
    if (root.hasMember("robot")) robot = root["robot"];
    const auto config = robot_sim::parseWorldConfig(world, "/sim/world", table, "/table", robot, "/robot");
    const auto found = config.robot.motors.find(argv[2]);
    if (found == config.robot.motors.end()) {
      std::fprintf(stderr, "motor_replay: no motor '%s' in /sim/world/robot/motors\n", argv[2]);
      return 2;
    }
    const robot_sim::MotorConfig& motor = found->second;
    robot_sim::MotorState state;
    double now = std::nan(""), turns = 0.0;
    auto advance = [&](double until) {  // the world's own step
      if (std::isnan(now)) now = until;
      while (now + config.dt <= until + 1e-12) {
        robot_sim::stepMotor(motor, state, config.dt);
        turns += state.speed * config.dt / (2.0 * M_PI);
        now += config.dt;
      }
    };
    std::string line;
    while (std::getline(std::cin, line)) {
      std::istringstream fields(line);
      char kind = 0;
      double t = 0.0;
      if (!(fields >> kind >> t)) continue;
      advance(t);
      if (kind == 'c') {
        double u = 0.0;
        fields >> u;
        state.command = u;
      } else if (kind == 'q') {
        std::printf("%.9f\n", turns);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "motor_replay: %s\n", e.what());
    return 1;
  }
  return 0;
}
