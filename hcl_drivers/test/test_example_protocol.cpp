#include <gtest/gtest.h>

#include "hcl_drivers/boards/example_protocol.h"

namespace ep = hcl_drivers::example_protocol;

TEST(ExampleProtocol, RequestBytes) {
  EXPECT_EQ(ep::encodeRequest(7, 200), (std::vector<uint8_t>{'E', 'X', 0x01, 7, 200}));
}

TEST(ExampleProtocol, ReplyDecodes) {
  auto r = ep::decodeReply({'E', 'X', 0x81, 9, 0xFF, 0x03, 128, 0x10, 0x27, 0x00, 0x00});
  ASSERT_TRUE(r);
  EXPECT_EQ(r->seq, 9);
  EXPECT_EQ(r->dial_raw, 1023);
  EXPECT_EQ(r->lamp_pwm, 128);
  EXPECT_EQ(r->uptime_ms, 10000u);
}

TEST(ExampleProtocol, MalformedRepliesAreRejected) {
  EXPECT_FALSE(ep::decodeReply({}));
  EXPECT_FALSE(ep::decodeReply({'E', 'X', 0x81, 9, 0, 0, 0, 0, 0, 0}));           // short
  EXPECT_FALSE(ep::decodeReply({'E', 'Y', 0x81, 9, 0, 0, 0, 0, 0, 0, 0}));        // magic
  EXPECT_FALSE(ep::decodeReply({'E', 'X', 0x01, 9, 0, 0, 0, 0, 0, 0, 0}));        // a request
  EXPECT_FALSE(ep::decodeReply({'E', 'X', 0x81, 9, 0x00, 0x04, 0, 0, 0, 0, 0}));  // dial 1024
}
