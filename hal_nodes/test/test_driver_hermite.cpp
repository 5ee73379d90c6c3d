// The maneuver's cubic Hermite curve: through every checkpoint, C1 at every join.
#include <gtest/gtest.h>

#include <cmath>

#include "hal_nodes/driver/hermite_path.h"

using namespace hal_nodes::driver;

namespace {
std::vector<Checkpoint> sixCheckpoints() {
  return {{0.8, 0.5}, {1.3, 0.9}, {1.8, 0.6}, {2.3, 1.2}, {1.8, 1.6, true, M_PI}, {1.0, 1.3}};
}
const Pose2D kStart{0.4, 0.4, 0.3};
}  // namespace

TEST(HermitePath, PassesThroughEveryCheckpoint) {
  const auto cps = sixCheckpoints();
  const HermitePath path(kStart, cps);
  ASSERT_EQ(path.segments(), 6);
  const Point2D s = path.position(0, 0.0);
  EXPECT_NEAR(s.x, kStart.x, 1e-12);
  EXPECT_NEAR(s.y, kStart.y, 1e-12);
  for (int i = 0; i < 6; ++i) {
    const Point2D e = path.position(i, 1.0);
    EXPECT_NEAR(e.x, cps[i].x, 1e-12) << "checkpoint " << i;
    EXPECT_NEAR(e.y, cps[i].y, 1e-12) << "checkpoint " << i;
    if (i + 1 < 6) {
      const Point2D b = path.position(i + 1, 0.0);
      EXPECT_NEAR(b.x, cps[i].x, 1e-12);
      EXPECT_NEAR(b.y, cps[i].y, 1e-12);
    }
  }
}

TEST(HermitePath, FirstDerivativeIsContinuousAtEveryJoin) {
  const HermitePath path(kStart, sixCheckpoints());
  for (int i = 0; i + 1 < path.segments(); ++i) {
    const Point2D a = path.derivative(i, 1.0), b = path.derivative(i + 1, 0.0);
    EXPECT_NEAR(a.x, b.x, 1e-12) << "join " << i;
    EXPECT_NEAR(a.y, b.y, 1e-12) << "join " << i;
    EXPECT_GT(std::hypot(a.x, a.y), 1e-3) << "a cusp is not smooth";
    // And numerically, from the positions either side of the join.
    const double h = 1e-6;
    const Point2D l = path.position(i, 1.0 - h), r = path.position(i + 1, h);
    EXPECT_NEAR((r.x - l.x) / (2 * h), a.x, 1e-4);
    EXPECT_NEAR((r.y - l.y) / (2 * h), a.y, 1e-4);
  }
}

TEST(HermitePath, DefaultTangentPointsToTheNextCheckpointAndHeadingsAreHonoured) {
  const auto cps = sixCheckpoints();
  const HermitePath path(kStart, cps);
  // Start: the robot's heading.
  const Point2D t0 = path.tangents()[0];
  EXPECT_NEAR(std::atan2(t0.y, t0.x), kStart.theta, 1e-12);
  // Checkpoint 0 (node 1): towards checkpoint 1.
  const Point2D t1 = path.tangents()[1];
  EXPECT_NEAR(std::atan2(t1.y, t1.x), std::atan2(cps[1].y - cps[0].y, cps[1].x - cps[0].x), 1e-12);
  // Checkpoint 4 fixes its heading.
  const Point2D t5 = path.tangents()[5];
  EXPECT_NEAR(std::fabs(std::remainder(std::atan2(t5.y, t5.x) - M_PI, 2 * M_PI)), 0.0, 1e-12);
  // The last one: along the incoming chord.
  const Point2D t6 = path.tangents()[6];
  EXPECT_NEAR(std::atan2(t6.y, t6.x), std::atan2(cps[5].y - cps[4].y, cps[5].x - cps[4].x), 1e-12);
}

TEST(HermitePath, SamplesAreDenseSmoothAndEndOnTheLastCheckpoint) {
  const HermitePath path(kStart, sixCheckpoints());
  const auto samples = path.sample(0.005);
  ASSERT_GT(samples.size(), 100u);
  EXPECT_NEAR(samples.back().x, 1.0, 1e-12);
  EXPECT_NEAR(samples.back().y, 1.3, 1e-12);
  for (std::size_t i = 1; i < samples.size(); ++i) {
    const double step = std::hypot(samples[i].x - samples[i - 1].x, samples[i].y - samples[i - 1].y);
    EXPECT_LT(step, 0.01);
    EXPECT_GT(samples[i].s, samples[i - 1].s);
    // No heading jump between neighbouring samples anywhere, joins included.
    EXPECT_LT(std::fabs(std::remainder(samples[i].heading - samples[i - 1].heading, 2 * M_PI)), 0.2) << "sample " << i;
  }
}

TEST(HermitePath, EmptyWithoutCheckpoints) {
  const HermitePath path(kStart, {});
  EXPECT_TRUE(path.empty());
  EXPECT_TRUE(path.sample(0.01).empty());
}

TEST(HermitePath, StartsAlongTheChordWhenTheRobotFacesAway) {
  // In a corner facing it (-135 deg), the next checkpoint out on the table behind the robot: the
  // curve must not loop forwards into the corner first.
  const Pose2D in_corner{0.30, 0.29, -2.36};
  const HermitePath path(in_corner, {{0.75, 1.04}, {1.14, 1.61}});
  for (const auto& p : path.sample(0.01)) {
    EXPECT_GE(p.x, in_corner.x - 1e-9);
    EXPECT_GE(p.y, in_corner.y - 1e-9);
  }
  // Facing less than 90 degrees off the chord, the robot's heading still starts the curve.
  const Pose2D sideways{0.30, 0.29, 0.0};
  const Point2D d = HermitePath(sideways, {{0.75, 1.04}}).derivative(0, 0.0);
  EXPECT_NEAR(std::atan2(d.y, d.x), 0.0, 1e-9);
}
