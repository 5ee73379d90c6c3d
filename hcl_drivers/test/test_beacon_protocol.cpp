// The beacon receiver's message parser: framing, checksum, resynchronisation.
#include <gtest/gtest.h>

#include <string>

#include "hcl_drivers/boards/beacon_protocol.h"

using namespace hcl_drivers::beacon_protocol;

namespace {
std::vector<Message> feedAll(Parser& p, const std::string& s) {
  std::vector<Message> out;
  p.feed(reinterpret_cast<const uint8_t*>(s.data()), s.size(), out);
  return out;
}
}  // namespace

TEST(BeaconProtocol, EncodesTheDocumentedExample) {
  EXPECT_EQ(encode({1, 4711}), "$B1,4711*5C\r\n");
  // 'B'^'0'^','^'0' = 0x42^0x30^0x2C^0x30 = 0x6E
  EXPECT_EQ(encode({0, 0}), "$B0,0*6E\r\n");
}

TEST(BeaconProtocol, ParsesValidMessages) {
  Parser p;
  const auto out = feedAll(p, "$B1,4711*5C\r\n$B0,0*6E\r\n$B2,999999*" + encode({2, 999999}).substr(11));
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].beacon_id, 1);
  EXPECT_EQ(out[0].delta_us, 4711u);
  EXPECT_EQ(out[1].delta_us, 0u);
  EXPECT_EQ(out[2].beacon_id, 2);
  EXPECT_EQ(out[2].delta_us, 999999u);
  EXPECT_EQ(p.stats().messages, 3u);
  EXPECT_EQ(p.stats().garbage_bytes, 0u);
}

TEST(BeaconProtocol, AnySplitOfTheStreamGivesTheSameMessages) {
  const std::string stream = encode({0, 123}) + "xx" + encode({1, 4567}) + encode({2, 89});
  for (std::size_t cut = 0; cut <= stream.size(); ++cut) {
    Parser p;
    auto out = feedAll(p, stream.substr(0, cut));
    const auto rest = feedAll(p, stream.substr(cut));
    out.insert(out.end(), rest.begin(), rest.end());
    ASSERT_EQ(out.size(), 3u) << "cut at " << cut;
    EXPECT_EQ(out[1].delta_us, 4567u);
    EXPECT_EQ(p.stats().garbage_bytes, 2u);
  }
}

TEST(BeaconProtocol, LowercaseChecksumAndBareLineFeedAreAccepted) {
  Parser p;
  EXPECT_EQ(feedAll(p, "$B1,4711*5c\n").size(), 1u);
}

TEST(BeaconProtocol, WrongChecksumIsCountedAndDropped) {
  Parser p;
  EXPECT_TRUE(feedAll(p, "$B1,4711*5D\r\n").empty());
  EXPECT_EQ(p.stats().checksum_errors, 1u);
  EXPECT_EQ(feedAll(p, encode({1, 5})).size(), 1u);
}

TEST(BeaconProtocol, ResynchronisesAfterGarbageAndTruncatedMessages) {
  Parser p;
  const std::string s = std::string("\x01\xff junk") + "$B1,47" + encode({2, 300}) + "$B0,12*" + "garbage\n" +
                        encode({0, 301});
  const auto out = feedAll(p, s);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].delta_us, 300u);
  EXPECT_EQ(out[1].delta_us, 301u);
  EXPECT_EQ(p.stats().garbage_bytes, 7u);  // "\x01\xff junk"
  EXPECT_EQ(p.stats().malformed, 2u);      // cut by '$', then "$B0,12*garbage\n"
}

TEST(BeaconProtocol, RejectsBadSyntax) {
  for (const char* bad : {"$B1,*4B\r\n", "$BX,1*00\r\n", "$B1,1234567*00\r\n", "$C1,1*00\r\n", "$B1;1*00\r\n",
                          "$B1,1a*00\r\n", "$B1,1*0\r\n", "$B1,1*0G\r\n", "$\r\n"}) {
    Parser p;
    EXPECT_TRUE(feedAll(p, bad).empty()) << bad;
    EXPECT_EQ(p.stats().malformed + p.stats().checksum_errors, 1u) << bad;
  }
}

TEST(BeaconProtocol, EndlessFrameIsDroppedAndTheNextMessageStillComes) {
  Parser p;
  const auto out = feedAll(p, "$B1,11111111111111111111111111111" + encode({1, 7}));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].delta_us, 7u);
  EXPECT_EQ(p.stats().malformed, 1u);
}
