// The rangers' filter: nonsense dropped, no-echo kept as +inf, peaks removed by the median,
// noise reduced by smoothing, real steps passed without smoothing lag.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "hal_nodes/devices/rangers/range_filter.h"

using namespace hal_nodes;

namespace {
constexpr double kMin = 0.15, kMax = 6.0;
const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();
}  // namespace

TEST(RangeFilter, NonsenseIsDroppedAndCounted) {
  RangeFilter f;
  RangeFilter::Verdict v;
  EXPECT_FALSE(f.add(kNaN, kMin, kMax, &v));
  EXPECT_EQ(v, RangeFilter::Verdict::kNonsense);
  EXPECT_FALSE(f.add(-1.0, kMin, kMax));
  EXPECT_FALSE(f.add(0.05, kMin, kMax));  // inside the blind zone
  EXPECT_EQ(f.nonsense(), 3u);
  ASSERT_TRUE(f.add(1.0, kMin, kMax));
  EXPECT_DOUBLE_EQ(*f.add(kNaN, kMin, kMax), 1.0);  // output held, not disturbed
  EXPECT_EQ(f.nonsense(), 4u);
}

TEST(RangeFilter, NoEchoBecomesInfinityOnlyWhenConsistent) {
  RangeFilter f;
  for (int i = 0; i < 5; ++i) f.add(1.0, kMin, kMax);
  RangeFilter::Verdict v;
  EXPECT_NEAR(*f.add(7.0, kMin, kMax, &v), 1.0, 1e-12);  // one missed echo: outvoted
  EXPECT_EQ(v, RangeFilter::Verdict::kNoEcho);
  f.add(kInf, kMin, kMax);
  EXPECT_TRUE(std::isinf(*f.add(kMax, kMin, kMax)));  // third in a row: majority of 5
}

TEST(RangeFilter, PeakIsRemoved) {
  RangeFilter f;
  for (int i = 0; i < 5; ++i) f.add(2.0, kMin, kMax);
  EXPECT_NEAR(*f.add(0.3, kMin, kMax), 2.0, 1e-12);  // cross-talk spike
  EXPECT_NEAR(*f.add(2.0, kMin, kMax), 2.0, 1e-12);
  EXPECT_NEAR(*f.add(0.3, kMin, kMax), 2.0, 1e-12);  // two spikes in five: still outvoted
}

TEST(RangeFilter, RealStepPassesWithinHalfTheWindowAndWithoutLag) {
  RangeFilter f;
  for (int i = 0; i < 5; ++i) f.add(2.0, kMin, kMax);
  f.add(0.5, kMin, kMax);
  f.add(0.5, kMin, kMax);
  EXPECT_NEAR(*f.add(0.5, kMin, kMax), 0.5, 1e-12);  // 3 of 5: the obstacle is there, no smoothing lag
}

TEST(RangeFilter, ANearerJumpPassesAtOnceWhenAskedAFartherOneStillWaits) {
  RangeFilterConfig c;
  c.nearer_at_once = true;
  RangeFilter f(c);
  for (int i = 0; i < 5; ++i) f.add(2.0, kMin, kMax);
  EXPECT_NEAR(*f.add(0.3, kMin, kMax), 0.3, 1e-12);  // something came close: at once
  EXPECT_NEAR(*f.add(0.3, kMin, kMax), 0.3, 1e-12);
  EXPECT_NEAR(*f.add(0.3, kMin, kMax), 0.3, 1e-12);
  // Farther is still a peak until confirmed (a missed echo must not clear an obstacle).
  EXPECT_NEAR(*f.add(2.0, kMin, kMax), 0.3, 1e-12);
  // Without the option the same nearer jump is held back by the median.
  RangeFilter g;
  for (int i = 0; i < 5; ++i) g.add(2.0, kMin, kMax);
  EXPECT_NEAR(*g.add(0.3, kMin, kMax), 2.0, 1e-12);
}

TEST(RangeFilter, NoiseIsReduced) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.02);
  RangeFilter f;
  double raw_ss = 0.0, out_ss = 0.0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    const double r = 1.0 + noise(rng);
    const double out = *f.add(r, kMin, kMax);
    if (i >= 10) {
      raw_ss += (r - 1.0) * (r - 1.0);
      out_ss += (out - 1.0) * (out - 1.0);
    }
  }
  EXPECT_LT(out_ss, 0.5 * raw_ss);  // the output's variance is under half the raw one
}

TEST(RangeFilter, ResetForgetsOldReadings) {
  RangeFilter f;
  for (int i = 0; i < 5; ++i) f.add(2.0, kMin, kMax);
  f.reset();
  EXPECT_FALSE(f.value());
  EXPECT_NEAR(*f.add(0.7, kMin, kMax), 0.7, 1e-12);
}

// An SRF02 sweeping along a wall while the robot turns (front_left of the simulated Logion
// leaving its start zone, 10 Hz): every reading is real. A median of 5 reports each range
// two readings late, and the driver takes the difference for an obstacle the border does not
// explain. The output must trail the reading by less than the last reading's change (the noise
// smoothing, smoothing 0.5), never by two readings; a change beyond `step` passes exactly.
TEST(RangeFilter, SweepAlongAWallIsNotDelayed) {
  RangeFilter f;
  const double sweep[] = {0.21, 0.21, 0.21, 0.24, 0.30, 0.36, 0.52, 0.74, 1.02, 1.34};
  double previous = sweep[0];
  for (double r : sweep) {
    const double out = *f.add(r, kMin, kMax);
    EXPECT_LE(std::abs(out - r), std::max(1e-12, r - previous)) << "reading " << r;
    if (r - previous > 0.10) {
      EXPECT_NEAR(out, r, 1e-12) << "reading " << r;
    }
    previous = r;
  }
}

TEST(RangeFilter, SlowDriftIsFollowedWithinTheSmoothingLag) {
  RangeFilter f;  // smoothing 0.5: lags a steady drift by one increment at most
  for (int i = 0; i < 30; ++i) {
    const double r = 1.0 + 0.04 * i;
    EXPECT_NEAR(*f.add(r, kMin, kMax), r, 0.04 + 1e-9) << "reading " << i;
  }
}

TEST(RangeFilter, JumpPassesOnceTheNextReadingContinuesIt) {
  RangeFilter f;
  for (int i = 0; i < 5; ++i) f.add(2.0, kMin, kMax);
  EXPECT_NEAR(*f.add(0.5, kMin, kMax), 2.0, 1e-12);  // alone: could be a spike
  EXPECT_NEAR(*f.add(0.5, kMin, kMax), 0.5, 1e-12);  // confirmed: the obstacle is there
}
