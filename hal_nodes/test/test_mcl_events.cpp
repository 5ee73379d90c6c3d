// The localization device's input queue: events come out in stamp order whatever their
// arrival order (what makes a replayed bag give the same filter steps run after run), only up
// to the watermark, with late and overflowing events counted, never silently reordered.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "../src/devices/localization/input_events.h"

using hal_nodes::localization::InputEvents;

TEST(InputEvents, ArrivalOrderDoesNotChangeTheSequence) {
  std::vector<std::pair<double, int>> events;
  for (int i = 0; i < 300; ++i) events.push_back({0.01 * (i / 3), i % 3 == 2 ? 1 : 0});  // ties at equal stamps
  std::vector<std::vector<std::pair<double, int>>> outputs;
  for (unsigned seed : {1u, 2u, 3u}) {
    auto shuffled = events;
    std::mt19937 g(seed);
    std::shuffle(shuffled.begin(), shuffled.end(), g);
    InputEvents<int> q(1000);
    for (const auto& e : shuffled) q.push(e.first, e.second, e.second);
    std::vector<std::pair<double, int>> out;
    for (double w : {0.3, 0.7, 1.0})  // batches at arbitrary refresh times
      for (const auto& e : q.takeUntil(w)) out.push_back({e.stamp, e.payload});
    outputs.push_back(out);
  }
  ASSERT_EQ(outputs[0].size(), 300u);
  EXPECT_EQ(outputs[0], outputs[1]);
  EXPECT_EQ(outputs[0], outputs[2]);
  for (std::size_t i = 1; i < outputs[0].size(); ++i) {
    ASSERT_LE(outputs[0][i - 1].first, outputs[0][i].first);
    if (outputs[0][i - 1].first == outputs[0][i].first) {
      ASSERT_LE(outputs[0][i - 1].second, outputs[0][i].second);
    }
  }
}

TEST(InputEvents, HoldsBackNewerThanTheWatermarkAndCountsLateAndDropped) {
  InputEvents<int> q(3);
  EXPECT_TRUE(q.push(1.0, 0, 1));
  EXPECT_TRUE(q.push(2.0, 0, 2));
  EXPECT_TRUE(q.push(3.0, 0, 3));
  EXPECT_FALSE(q.push(4.0, 0, 4));  // full
  EXPECT_EQ(q.dropped(), 1u);
  auto a = q.takeUntil(2.0);
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a[0].payload, 1);
  EXPECT_EQ(q.size(), 1u);
  q.push(1.5, 0, 5);  // older than what was handed out: too late
  auto b = q.takeUntil(10.0);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(b[0].payload, 3);
  EXPECT_EQ(q.late(), 1u);
}
