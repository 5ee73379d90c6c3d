#include "robot_core/command_gate.h"

#include <arpa/inet.h>
#include <diagnostic_msgs/DiagnosticArray.h>
#include <ifaddrs.h>
#include <netdb.h>
#include <netinet/in.h>
#include <ros/master.h>

#include <sstream>
#include <stdexcept>

#include "robot_core/params.h"

namespace robot_core {

namespace {

constexpr double kLookupTtl = 10.0;  // [s] a sender's host is asked again after this long

double wallNow() { return ros::WallTime::now().toSec(); }

// The IPv4 address `host` (a dotted address or a name) stands for; false when it resolves to none.
bool resolve(const std::string& host, uint32_t& out) {
  in_addr a{};
  if (inet_pton(AF_INET, host.c_str(), &a) == 1) {
    out = ntohl(a.s_addr);
    return true;
  }
  addrinfo hints{};
  hints.ai_family = AF_INET;
  addrinfo* res = nullptr;
  if (getaddrinfo(host.c_str(), nullptr, &hints, &res) != 0 || !res) return false;
  out = ntohl(reinterpret_cast<sockaddr_in*>(res->ai_addr)->sin_addr.s_addr);
  freeaddrinfo(res);
  return true;
}

std::string dotted(uint32_t a) {
  in_addr n{};
  n.s_addr = htonl(a);
  char buf[INET_ADDRSTRLEN];
  inet_ntop(AF_INET, &n, buf, sizeof buf);
  return buf;
}

// An entry of robot_hosts or allow as the installer takes it: a.b.c.d or a.b.c.0/n, no host bits.
bool strictNetwork(const std::string& text) {
  Ipv4Net net;
  try {
    net = Ipv4Net::parse(text);
  } catch (const std::invalid_argument&) {
    return false;
  }
  const uint32_t mask = net.prefix == 0 ? 0u : ~0u << (32 - net.prefix);
  return (net.address & ~mask) == 0;
}

// Why `address` is no address of the robot ("" when it is one).
std::string addressProblem(const std::string& address) {
  Ipv4Net ip;
  try {
    ip = Ipv4Net::parse(address);
  } catch (const std::invalid_argument&) {
    return "'" + address + "' is not an IPv4 address";
  }
  if (address.find('/') != std::string::npos) return "'" + address + "' is not an IPv4 address";
  if (ip.address == 0 || (ip.address >> 28) == 0xEu) return address + " is not an address of the robot";
  return "";
}

}  // namespace

bool Ipv4Net::contains(uint32_t a) const {
  const uint32_t mask = prefix == 0 ? 0u : ~0u << (32 - prefix);
  return (a & mask) == (address & mask);
}

// a.b.c.d or a.b.c.d/n (n: 1 or 2 digits), the one form the Python reader (network_settings.py) takes.
Ipv4Net Ipv4Net::parse(const std::string& text) {
  Ipv4Net net;
  const auto first = text.find_first_not_of(" \t"), last = text.find_last_not_of(" \t");
  const std::string trimmed = first == std::string::npos ? "" : text.substr(first, last - first + 1);
  const auto slash = trimmed.find('/');
  const std::string addr = trimmed.substr(0, slash);
  in_addr a{};
  if (inet_pton(AF_INET, addr.c_str(), &a) != 1) throw std::invalid_argument("'" + text + "' is no IPv4 address or network");
  net.address = ntohl(a.s_addr);
  if (slash != std::string::npos) {
    const std::string prefix = trimmed.substr(slash + 1);
    const bool digits = !prefix.empty() && prefix.size() <= 2 &&
                        prefix.find_first_not_of("0123456789") == std::string::npos;
    net.prefix = digits ? std::stoi(prefix) : -1;
    if (net.prefix < 0 || net.prefix > 32) throw std::invalid_argument("'" + text + "': the prefix must be 0..32");
  }
  return net;
}

RobotNetwork::RobotNetwork(const std::vector<std::string>& trusted) {
  nets_.push_back(Ipv4Net::parse("127.0.0.0/8"));
  for (const auto& t : trusted) nets_.push_back(Ipv4Net::parse(t));
  // This computer's own addresses: a node here that registered with its LAN address is ours.
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) == 0) {
    for (ifaddrs* i = list; i; i = i->ifa_next)
      if (i->ifa_addr && i->ifa_addr->sa_family == AF_INET) {
        Ipv4Net own;
        own.address = ntohl(reinterpret_cast<sockaddr_in*>(i->ifa_addr)->sin_addr.s_addr);
        nets_.push_back(own);
      }
    freeifaddrs(list);
  }
}

RobotNetwork RobotNetwork::fromParams(const Params& network) {
  // The keys, meanings and refusals of robot_core/network_settings.py (the Python nodes' and the
  // installer's reader), in its order: every key read, an unknown one refused, then the values.
  const std::string address = network.optionalString("address", "127.0.0.1");
  network.describe("address",
                   "the robot's own address: ROS_IP of its nodes, its master at http://address:master_port "
                   "(loopback on one computer)");
  const int port = network.optionalInt("master_port", 11311);
  network.describe("master_port", "the ROS master's TCP port (ROS_MASTER_URI), opened by the firewall");
  const std::vector<std::string> robot_hosts = network.optionalStringList("robot_hosts");
  network.describe("robot_hosts", "the robot's other computers (two-computer deployment): their nodes are the robot's");
  const std::vector<std::string> allow = network.optionalStringList("allow");
  network.describe("allow",
                   "laptops let in (rviz, the team's tools): trusted, not the robot; for one match: make allow-laptop");
  const std::vector<std::string> unknown = network.unasked();
  if (!unknown.empty()) {
    const std::string& line = unknown.front();  // "<ns>/<key> = <value>"
    const std::size_t from = network.ns().size() + 1;
    std::string known;
    for (const auto& k : network.askedKeys()) known += (known.empty() ? "" : ", ") + k;
    network.check(line.substr(from, line.find(" = ") - from), "unknown key (" + known + ")");
  }
  network.check("address", addressProblem(address));
  if (port < 1 || port > 65535) network.check("master_port", std::to_string(port) + " is not a port (1..65535)");
  std::vector<std::string> trusted{address};
  for (const auto& [key, entries] : {std::make_pair("robot_hosts", &robot_hosts), std::make_pair("allow", &allow)})
    for (const auto& entry : *entries) {
      if (!strictNetwork(entry))
        network.check(key, "'" + entry + "' is not an IPv4 address or network (a.b.c.d or a.b.c.0/24)");
      trusted.push_back(entry);
    }
  return RobotNetwork(trusted);
}

RobotNetwork RobotNetwork::fromParameters() {
  try {
    return fromParams(Params::of(ros::NodeHandle("/computer")).block("network"));
  } catch (const std::exception& e) {  // ParameterError; std::invalid_argument from Ipv4Net::parse
    ROS_ERROR("command gate: %s; only this computer is trusted", e.what());
    return RobotNetwork(std::vector<std::string>{});
  }
}

bool RobotNetwork::trusted(uint32_t address) const {
  for (const auto& n : nets_)
    if (n.contains(address)) return true;
  return false;
}

bool RobotNetwork::trusted(const std::string& dotted_address) const {
  uint32_t a = 0;
  return resolve(dotted_address, a) && trusted(a);
}

CommandGate& CommandGate::instance() {
  static CommandGate gate;
  return gate;
}

CommandGate::CommandGate() : network_(RobotNetwork::fromParameters()) {
  ros::NodeHandle nh;
  match_end_sub_ = nh.subscribe<std_msgs::Time>("/effectors/match_end", 1, [this](const std_msgs::Time::ConstPtr& m) {
    std::lock_guard<std::mutex> lk(mutex_);
    match_end_ = m->data;
  });
  diagnostics_pub_ = nh.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
  report_timer_ = nh.createWallTimer(ros::WallDuration(1.0), &CommandGate::report, this);
}

bool CommandGate::matchRunning() const {
  return !match_end_.isZero() && ros::Time::now() < match_end_;
}

CommandGate::Origin CommandGate::lookup(const std::string& caller) const {
  Origin o;
  o.looked_up = wallNow();
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = caller;
  std::string uri;
  if (ros::master::execute("lookupNode", args, result, payload, false) && payload.getType() == XmlRpc::XmlRpcValue::TypeString)
    uri = static_cast<std::string>(payload);
  // http://HOST:PORT/
  const auto start = uri.find("://");
  const std::string host = start == std::string::npos ? "" : uri.substr(start + 3, uri.find(':', start + 3) - start - 3);
  uint32_t a = 0;
  if (host.empty()) {
    o.host = "unknown to the master";
    o.foreign = true;
  } else if (!resolve(host, a)) {
    o.host = host + " (unresolved)";
    o.foreign = true;
  } else {
    o.host = dotted(a);
    o.foreign = !network_.trusted(a);
  }
  return o;
}

bool CommandGate::accept(const std::string& caller, const std::string& what) {
  // This process's own commands (a device commanding another in the same hal_node): no lookup.
  if (caller == ros::this_node::getName()) return true;
  bool ask_master = true;
  {
    std::lock_guard<std::mutex> lk(mutex_);
    const auto it = senders_.find(caller);
    if (it != senders_.end()) {
      // A trusted sender stays trusted (no XML-RPC on the command path of the robot's own nodes);
      // a foreign or unknown one is asked about again after kLookupTtl (it may have been a
      // node restarted on the robot under the same name).
      if (!it->second.origin.foreign) return true;
      ask_master = wallNow() - it->second.origin.looked_up >= kLookupTtl;
    }
  }
  Origin fresh;
  if (ask_master) fresh = lookup(caller);  // the master, without holding the gate
  std::lock_guard<std::mutex> lk(mutex_);
  Sender& s = senders_[caller];
  if (ask_master) s.origin = std::move(fresh);
  if (!s.origin.foreign) return true;
  s.last_what = what;
  if (!matchRunning()) {
    ++s.obeyed;
    ROS_WARN_THROTTLE(5.0, "command gate: %s from %s at %s, outside the robot's network (obeyed: no match running)",
                      what.c_str(), caller.c_str(), s.origin.host.c_str());
    return true;
  }
  ++s.refused;
  ROS_ERROR_THROTTLE(1.0, "command gate: %s from %s at %s, outside the robot's network, ignored during the match",
                     what.c_str(), caller.c_str(), s.origin.host.c_str());
  return false;
}

void CommandGate::report(const ros::WallTimerEvent&) {
  diagnostic_msgs::DiagnosticArray out;
  {
    std::lock_guard<std::mutex> lk(mutex_);
    for (const auto& entry : senders_) {
      const Sender& s = entry.second;
      if (!s.origin.foreign || (s.obeyed == 0 && s.refused == 0)) continue;
      diagnostic_msgs::DiagnosticStatus st;
      st.name = "command gate " + ros::this_node::getName() + ": " + entry.first;
      st.hardware_id = s.origin.host;
      st.level = s.refused ? diagnostic_msgs::DiagnosticStatus::ERROR : diagnostic_msgs::DiagnosticStatus::WARN;
      std::ostringstream m;
      m << "commands from " << entry.first << " at " << s.origin.host << ", outside the robot's network: " << s.refused
        << " ignored during a match, " << s.obeyed << " obeyed outside a match (last: " << s.last_what << ")";
      st.message = m.str();
      diagnostic_msgs::KeyValue kv;
      kv.key = "ignored";
      kv.value = std::to_string(s.refused);
      st.values.push_back(kv);
      kv.key = "obeyed";
      kv.value = std::to_string(s.obeyed);
      st.values.push_back(kv);
      out.status.push_back(st);
    }
  }
  if (out.status.empty()) return;
  out.header.stamp = ros::Time::now();
  diagnostics_pub_.publish(out);
}

}  // namespace robot_core
