#include <gtest/gtest.h>

#include "hcl_drivers/transport/endpoint.h"

using hcl_drivers::transport::parseEndpoint;

TEST(Endpoint, Udp) {
  auto e = parseEndpoint("udp://127.0.0.1:27100");
  EXPECT_EQ(e.scheme, "udp");
  EXPECT_EQ(e.host, "127.0.0.1");
  EXPECT_EQ(e.port, 27100);
}

TEST(Endpoint, SocketCanSimAndDevice) {
  EXPECT_EQ(parseEndpoint("socketcan://vcan0").host, "vcan0");
  EXPECT_EQ(parseEndpoint("sim:///run/robot_sim/i2c-1").path, "/run/robot_sim/i2c-1");
  auto dev = parseEndpoint("/dev/i2c-1");
  EXPECT_EQ(dev.scheme, "file");
  EXPECT_EQ(dev.path, "/dev/i2c-1");
}

TEST(Endpoint, BadInputIsRejectedWithAReason) {
  for (const char* bad : {"", "udp://127.0.0.1", "udp://127.0.0.1:0", "udp://127.0.0.1:70000", "udp://h:12x",
                          "tcp://x:1", "socketcan://", "relative/path", "sim://relative"}) {
    EXPECT_THROW(parseEndpoint(bad), std::invalid_argument) << bad;
  }
}
