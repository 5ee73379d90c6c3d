#include <gtest/gtest.h>

#include <cmath>

#include "match_panel/match_clock.h"

using match_panel::countDown;
using match_panel::formatClock;

TEST(MatchClock, FormatsMinutesSecondsTenths) {
  EXPECT_EQ("1:23.4", formatClock(83.4));
  EXPECT_EQ("1:30.0", formatClock(90.0));
  EXPECT_EQ("0:05.0", formatClock(5.0));
  EXPECT_EQ("10:00.0", formatClock(600.0));
}

TEST(MatchClock, CutsTenthsSoItNeverShowsMoreThanLeft) {
  EXPECT_EQ("1:29.9", formatClock(89.99));
  EXPECT_EQ("0:00.0", formatClock(0.09));
}

TEST(MatchClock, NegativeAndNanShowZero) {
  EXPECT_EQ("0:00.0", formatClock(-3.0));
  EXPECT_EQ("0:00.0", formatClock(std::nan("")));
}

TEST(MatchClock, CountsDownOnlyWhileRunning) {
  EXPECT_DOUBLE_EQ(80.0, countDown(90.0, 10.0, true));
  EXPECT_DOUBLE_EQ(90.0, countDown(90.0, 10.0, false));  // before the start: the full match
  EXPECT_DOUBLE_EQ(0.0, countDown(5.0, 10.0, true));     // never below 0
  EXPECT_DOUBLE_EQ(50.0, countDown(50.0, -2.0, true));   // a stamp from the future adds nothing
}
