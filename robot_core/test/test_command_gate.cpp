// The command gate's pure parts: parsing the config's addresses and networks, and who is trusted.
#include <arpa/inet.h>
#include <gtest/gtest.h>

#include <stdexcept>

#include "robot_core/command_gate.h"
#include "robot_core/params.h"

using robot_core::Ipv4Net;
using robot_core::ParameterError;
using robot_core::Params;
using robot_core::RobotNetwork;

namespace {

XmlRpc::XmlRpcValue strings(const std::vector<std::string>& items) {
  XmlRpc::XmlRpcValue out;
  out.setSize(static_cast<int>(items.size()));
  for (std::size_t i = 0; i < items.size(); ++i) out[static_cast<int>(i)] = items[i];
  return out;
}

// The error line of reading `network` as computer/network ("" when it is accepted).
std::string refusal(const XmlRpc::XmlRpcValue& network) {
  XmlRpc::XmlRpcValue computer;
  computer["network"] = network;
  try {
    RobotNetwork::fromParams(Params(computer, "/computer").block("network"));
  } catch (const ParameterError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Ipv4Net, ParsesAddressesAndNetworks) {
  const Ipv4Net host = Ipv4Net::parse("10.0.0.2");
  EXPECT_EQ(host.prefix, 32);
  EXPECT_TRUE(host.contains(0x0A000002u));
  EXPECT_FALSE(host.contains(0x0A000003u));
  const Ipv4Net net = Ipv4Net::parse("192.168.1.0/24");
  EXPECT_TRUE(net.contains(0xC0A801FEu));
  EXPECT_FALSE(net.contains(0xC0A80201u));
  EXPECT_TRUE(Ipv4Net::parse("0.0.0.0/0").contains(0x01020304u));
}

TEST(Ipv4Net, RefusesWhatIsNoAddress) {
  EXPECT_THROW(Ipv4Net::parse("robot.local"), std::invalid_argument);
  EXPECT_THROW(Ipv4Net::parse("10.0.0.1/33"), std::invalid_argument);
  EXPECT_THROW(Ipv4Net::parse("10.0.0.1/x"), std::invalid_argument);
  EXPECT_THROW(Ipv4Net::parse("10.0.0"), std::invalid_argument);
}

TEST(RobotNetwork, TrustsLoopbackTheRobotAndTheAllowList) {
  const RobotNetwork net({"10.9.8.1", "10.9.7.0/30"});
  EXPECT_TRUE(net.trusted("127.0.0.1"));
  EXPECT_TRUE(net.trusted("127.3.2.1"));
  EXPECT_TRUE(net.trusted("10.9.8.1"));
  EXPECT_TRUE(net.trusted("10.9.7.2"));
  EXPECT_FALSE(net.trusted("10.9.7.4"));
  EXPECT_FALSE(net.trusted("10.9.8.2"));
  EXPECT_FALSE(net.trusted("not an address"));
}

TEST(RobotNetwork, ReadsComputerNetworkAsThePythonReader) {
  XmlRpc::XmlRpcValue network;
  network["address"] = "10.9.8.1";
  network["master_port"] = 11312;
  network["robot_hosts"] = strings({"10.9.8.2"});
  network["allow"] = strings({"10.9.7.0/30"});
  XmlRpc::XmlRpcValue computer;
  computer["network"] = network;
  const Params params(computer, "/computer");
  const RobotNetwork net = RobotNetwork::fromParams(params.block("network"));
  EXPECT_TRUE(net.trusted("10.9.8.1"));
  EXPECT_TRUE(net.trusted("10.9.8.2"));
  EXPECT_TRUE(net.trusted("10.9.7.3"));
  EXPECT_FALSE(net.trusted("10.9.6.1"));
  const auto declared = params["network"].declarations();
  ASSERT_EQ(declared.size(), 4u);
  for (const auto& [name, d] : declared) EXPECT_FALSE(d.meaning.empty()) << name;
}

TEST(RobotNetwork, RefusesWhatTheInstallerRefuses) {
  XmlRpc::XmlRpcValue address;
  address["address"] = "robot.local";
  EXPECT_EQ(refusal(address), "parameter /computer/network/address: 'robot.local' is not an IPv4 address");
  address["address"] = "0.0.0.0";
  EXPECT_EQ(refusal(address), "parameter /computer/network/address: 0.0.0.0 is not an address of the robot");
  XmlRpc::XmlRpcValue port;
  port["master_port"] = 70000;
  EXPECT_EQ(refusal(port), "parameter /computer/network/master_port: 70000 is not a port (1..65535)");
  XmlRpc::XmlRpcValue allow;
  allow["allow"] = strings({"10.9.7.1/30"});
  EXPECT_EQ(refusal(allow), "parameter /computer/network/allow: '10.9.7.1/30' is not an IPv4 address or network "
                            "(a.b.c.d or a.b.c.0/24)");
  XmlRpc::XmlRpcValue typo;
  typo["adress"] = "10.9.8.1";
  EXPECT_EQ(refusal(typo),
            "parameter /computer/network/adress: unknown key (address, allow, master_port, robot_hosts)");
}
