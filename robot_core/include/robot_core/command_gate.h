// Commands from outside the robot are not obeyed during a match.
//
// ROS 1 has no authentication: anyone who reaches the master can publish cmd_vel or call a
// service (a team's laptop pointed at the wrong robot, in the pits' shared Wi-Fi). The firewall
// that make install-robot installs keeps them out; this gate is the robot's own check behind it.
// A command (a message on a command topic, a service call) names its sender, a node; the gate
// asks the master where that node lives and compares the host with the robot's network:
//   127.0.0.0/8, this computer's own addresses, and the config's computer/network: address,
//   robot_hosts and allow (addresses or CIDR networks; the allow-list: the team's laptop).
// A sender elsewhere is "foreign". Outside a match its commands are obeyed and reported; during a
// match (HAL's latched /effectors/match_end is in the future) they are dropped. Either way it is
// said on /diagnostics ("command gate <node>", WARN outside a match, ERROR once one was dropped)
// and logged, throttled. A sender the master does not know is foreign too.
//
// One gate per process (instance()), shared by every subscriber and service of it; thread-safe.
// A sender is looked up once (an XML-RPC call to the master, outside the gate's lock); a trusted
// one is never asked about again, a foreign one every ~10 s. The process's own commands pass
// without a lookup.
#pragma once

#include <ros/ros.h>
#include <std_msgs/Time.h>

#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace robot_core {

class Params;

// An IPv4 network: address and prefix length ("10.0.0.2" is 10.0.0.2/32).
struct Ipv4Net {
  uint32_t address = 0;  // host byte order
  int prefix = 32;
  bool contains(uint32_t a) const;
  // Throws std::invalid_argument naming `text` when it is neither a.b.c.d nor a.b.c.d/n.
  static Ipv4Net parse(const std::string& text);
};

// The robot's network from computer/network (missing keys: loopback only) plus this computer's
// interface addresses. Pure but fromParameters (the parameter server).
class RobotNetwork {
 public:
  RobotNetwork() = default;
  explicit RobotNetwork(const std::vector<std::string>& trusted);  // addresses or networks
  // From `network`, computer/network read as robot_core/network_settings.py reads it (address,
  // master_port, robot_hosts, allow; an unknown key refused). Throws ParameterError naming a bad value.
  static RobotNetwork fromParams(const Params& network);
  // From the parameter server's /computer/network; on a bad value an ERROR and only this computer.
  static RobotNetwork fromParameters();
  bool trusted(uint32_t address) const;
  bool trusted(const std::string& dotted) const;

 private:
  std::vector<Ipv4Net> nets_;
};

class CommandGate {
 public:
  static CommandGate& instance();
  // True: obey `what` (a topic or service name) from node `caller`. False: the caller is foreign
  // and a match runs; the command must be dropped (counted and reported here).
  bool accept(const std::string& caller, const std::string& what);

 private:
  CommandGate();
  // Where a sender is, as the master said.
  struct Origin {
    bool foreign = false;
    std::string host;         // the address its URI names, or why it is unknown
    double looked_up = -1e9;  // wall time [s]
  };
  struct Sender {
    Origin origin;
    unsigned long obeyed = 0, refused = 0;
    std::string last_what;
  };
  Origin lookup(const std::string& caller) const;  // asks the master; called without mutex_
  bool matchRunning() const;
  void report(const ros::WallTimerEvent&);

  std::mutex mutex_;
  RobotNetwork network_;
  std::map<std::string, Sender> senders_;
  ros::Time match_end_;
  ros::Subscriber match_end_sub_;
  ros::Publisher diagnostics_pub_;
  ros::WallTimer report_timer_;
};

}  // namespace robot_core
