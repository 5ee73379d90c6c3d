// The beacons' delta -> distance equation and its least-squares fit.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hal_nodes/devices/beacons/beacon_equation.h"

using namespace hal_nodes;

TEST(BeaconEquation, SpeedOfSoundFollowsTemperature) {
  EXPECT_NEAR(speedOfSound(0.0), 331.3, 1e-9);
  EXPECT_NEAR(speedOfSound(20.0), 343.2, 0.1);
  EXPECT_GT(speedOfSound(30.0), speedOfSound(10.0));
}

TEST(BeaconEquation, DistanceWithOffsets) {
  BeaconEquation eq;
  eq.temperature = 20.0;
  eq.offset = 0.05;
  eq.beacon_offsets = {0.0, -0.02};
  const double c = speedOfSound(20.0);
  EXPECT_NEAR(eq.distance(0, 0.005), c * 0.005 + 0.05, 1e-12);
  EXPECT_NEAR(eq.distance(1, 0.005), c * 0.005 + 0.03, 1e-12);
  EXPECT_NEAR(eq.distance(2, 0.005), c * 0.005 + 0.05, 1e-12);  // no offset configured for id 2
}

TEST(BeaconEquation, FitRecoversScaleAndOffsetFromNoisyPairs) {
  BeaconEquation truth;
  truth.temperature = 25.0;
  truth.scale = 1.03;
  truth.offset = -0.04;
  truth.beacon_offsets = {0.01, 0.0, -0.01};
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.005);
  std::vector<double> delta, dist;
  std::vector<int> ids;
  for (int i = 0; i < 60; ++i) {
    const int id = i % 3;
    const double d = 0.3 + 3.0 * i / 60.0;
    delta.push_back((d - truth.offset - truth.beacon_offsets[id]) / (truth.scale * speedOfSound(truth.temperature)));
    dist.push_back(d + noise(rng));
    ids.push_back(id);
  }
  BeaconEquation eq;
  eq.temperature = 25.0;
  eq.beacon_offsets = truth.beacon_offsets;
  const LineFit f = fitEquation(eq, delta, dist, ids);
  ASSERT_TRUE(f.ok) << f.why;
  EXPECT_NEAR(eq.scale, 1.03, 0.005);
  EXPECT_NEAR(eq.offset, -0.04, 0.005);
  EXPECT_LT(f.rms, 0.008);
  EXPECT_GT(f.rms, 0.002);
}

TEST(BeaconEquation, FitRefusesDegenerateInput) {
  BeaconEquation eq;
  EXPECT_FALSE(fitEquation(eq, {0.001}, {0.3}, {}).ok);
  EXPECT_FALSE(fitEquation(eq, {0.001, 0.001}, {0.3, 0.4}, {}).ok);
  EXPECT_FALSE(fitEquation(eq, {0.001, 0.002}, {0.3}, {}).ok);
  EXPECT_FALSE(fitEquation(eq, {0.001, 0.002}, {0.5, 0.3}, {}).ok);  // negative speed
  EXPECT_FALSE(fitEquation(eq, {0.001, 0.002}, {0.3, 0.6}, {0}).ok);
  EXPECT_EQ(eq.scale, 1.0);  // untouched by failed fits
}
