// The command gate's pure parts: parsing the config's addresses and networks, and who is trusted.
#include <arpa/inet.h>
#include <gtest/gtest.h>

#include <stdexcept>

#include "robot_core/command_gate.h"

using robot_core::Ipv4Net;
using robot_core::RobotNetwork;

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
