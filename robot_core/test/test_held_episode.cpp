#include <gtest/gtest.h>

#include "robot_core/held_episode.h"

using robot_core::HeldEpisode;

namespace {
ros::Time at(double s) { return ros::Time(s); }
}  // namespace

TEST(HeldEpisode, NothingGrownIsNothingShown) {
  HeldEpisode e(1.0);
  EXPECT_FALSE(e.see(0, at(5.0)));
  EXPECT_FALSE(e.shown(at(5.0)));
  EXPECT_EQ(e.count(), 0u);
}

TEST(HeldEpisode, AGrowthIsShownForTheHoldAfterTheLast) {
  HeldEpisode e(1.0);
  e.see(0, at(10.0));
  EXPECT_TRUE(e.see(2, at(10.05)));  // a new episode
  EXPECT_TRUE(e.shown(at(10.05)));
  EXPECT_FALSE(e.see(3, at(10.5)));  // the same episode, held from its last growth
  EXPECT_EQ(e.count(), 3u);
  e.see(3, at(11.2));
  EXPECT_TRUE(e.shown(at(11.2)));
  EXPECT_FALSE(e.shown(at(11.5)));  // 1 s after the last growth
}

TEST(HeldEpisode, ANewEpisodeCountsFromItsStart) {
  HeldEpisode e(1.0);
  e.see(0, at(1.0));
  e.see(4, at(1.1));
  e.see(4, at(3.0));  // over
  EXPECT_TRUE(e.see(5, at(3.05)));
  EXPECT_EQ(e.count(), 1u);
}

TEST(HeldEpisode, ACountTakenIsNotAnEpisode) {
  HeldEpisode e(1.0);
  e.take(7);  // a power-on's boot-ups, a bus's past
  EXPECT_FALSE(e.shown(at(2.0)));
  EXPECT_FALSE(e.see(7, at(2.0)));
  EXPECT_TRUE(e.see(8, at(2.1)));
  EXPECT_EQ(e.count(), 1u);
}

TEST(HeldEpisode, AClockThatWentBackEndsTheEpisode) {
  HeldEpisode e(1.0);
  e.see(0, at(50.0));
  e.see(1, at(50.1));
  EXPECT_TRUE(e.shown(at(50.2)));
  EXPECT_FALSE(e.shown(at(0.3)));  // a restarted simulation
  EXPECT_TRUE(e.see(2, at(0.4)));
  EXPECT_EQ(e.count(), 1u);
}
