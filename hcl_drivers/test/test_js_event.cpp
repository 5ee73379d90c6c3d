// The js_event decoder and stick model.
#include <gtest/gtest.h>

#include <cstring>

#include "hcl_drivers/boards/js_event.h"

using namespace hcl_drivers::js;

namespace {
std::vector<uint8_t> record(uint32_t t, int16_t v, uint8_t type, uint8_t n) {
  std::vector<uint8_t> r(8);
  std::memcpy(r.data(), &t, 4);
  std::memcpy(r.data() + 4, &v, 2);
  r[6] = type;
  r[7] = n;
  return r;
}
}  // namespace

TEST(JsEvent, DecodesRecordsSplitAnywhere) {
  std::vector<uint8_t> stream;
  for (auto r : {record(10, 1, kButton | kInit, 0), record(11, -32767, kAxis | kInit, 1), record(500, 1234, kAxis, 3)})
    stream.insert(stream.end(), r.begin(), r.end());
  for (std::size_t cut = 0; cut <= stream.size(); ++cut) {
    Decoder d;
    std::vector<Event> out;
    d.feed(stream.data(), cut, out);
    d.feed(stream.data() + cut, stream.size() - cut, out);
    ASSERT_EQ(out.size(), 3u) << cut;
    EXPECT_EQ(out[0].type, kButton | kInit);
    EXPECT_EQ(out[1].value, -32767);
    EXPECT_EQ(out[2].time_ms, 500u);
    EXPECT_EQ(out[2].number, 3);
  }
}

TEST(JsEvent, StateFollowsInitAndLiveEvents) {
  State s;
  s.resize(2, 2);
  EXPECT_TRUE(s.apply({0, 1, kButton | kInit, 1}));
  EXPECT_TRUE(s.apply({0, 16000, kAxis | kInit, 0}));
  EXPECT_TRUE(s.apply({5, -32768, kAxis, 4}));  // grows; -32768 folds to -32767
  ASSERT_EQ(s.axes().size(), 5u);
  EXPECT_EQ(s.axes()[0], 16000);
  EXPECT_EQ(s.axes()[4], -32767);
  EXPECT_EQ(s.buttons()[1], 1);
  EXPECT_TRUE(s.apply({6, 0, kButton, 1}));
  EXPECT_EQ(s.buttons()[1], 0);
  s.clear();
  EXPECT_EQ(s.axes()[0], 0);
}

TEST(JsEvent, BadEventsAreRejected) {
  State s;
  EXPECT_FALSE(s.apply({0, 1, 0x04, 0}));         // unknown type
  EXPECT_FALSE(s.apply({0, 1, kAxis, 200}));      // beyond ABS_CNT
  EXPECT_FALSE(s.apply({0, 7, kButton, 0}));      // a button is 0 or 1
  EXPECT_TRUE(s.axes().empty());
  EXPECT_TRUE(s.buttons().empty());
}

TEST(JsEvent, DeadzoneIsContinuousAndReachesFullScale) {
  EXPECT_EQ(applyDeadzone(0, 0.1), 0.0);
  EXPECT_EQ(applyDeadzone(3000, 0.1), 0.0);        // 0.0916 < 0.1
  EXPECT_NEAR(applyDeadzone(32767, 0.1), 1.0, 1e-12);
  EXPECT_NEAR(applyDeadzone(-32767, 0.1), -1.0, 1e-12);
  EXPECT_NEAR(applyDeadzone(3277, 0.1), 0.0, 1e-3);  // just past the edge: near 0, no jump
  EXPECT_NEAR(applyDeadzone(16384, 0.0), 0.5, 1e-4);
  EXPECT_NEAR(applyDeadzone(16384, 0.2), (0.5 - 0.2) / 0.8, 1e-4);
}
