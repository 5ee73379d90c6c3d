// Odometry integration: encoder unwrapping (wrap-around, board resets), the wheel-pair model
// and the pose integrator on straight lines, arcs and spins, pair fusion, covariance growth.
#include <gtest/gtest.h>

#include <cmath>

#include "hal_nodes/devices/odometry/encoder_tracker.h"
#include "hal_nodes/devices/odometry/pair_alignment.h"
#include "hal_nodes/devices/odometry/pose_integrator.h"
#include "hal_nodes/devices/odometry/wheel_pair.h"

using namespace hal_nodes;

namespace {

constexpr double kTicksPerMeter = 20000.0;
constexpr double kTrack = 0.30;

WheelPairModel model() {
  WheelPairModel m;
  m.left_m_per_tick = 1.0 / kTicksPerMeter;
  m.right_m_per_tick = 1.0 / kTicksPerMeter;
  m.track_width = kTrack;
  return m;
}

// Drive wheel surfaces by (dl, dr) metres in `steps` equal samples through 16-bit counters
// starting at `start`, and integrate what the trackers see.
Pose2D drive(PoseIntegrator& integ, double dl, double dr, int steps, uint32_t start = 0, uint8_t bits = 16) {
  EncoderTracker tl, tr;
  const WheelPairModel m = model();
  const uint32_t mask = bits == 32 ? 0xffffffffu : ((1u << bits) - 1u);
  tl.update(start & mask, bits, 0);
  tr.update(start & mask, bits, 0);
  for (int i = 1; i <= steps; ++i) {
    const auto l = static_cast<int64_t>(std::llround(dl * kTicksPerMeter * i / steps));
    const auto r = static_cast<int64_t>(std::llround(dr * kTicksPerMeter * i / steps));
    const int64_t dL = tl.update(static_cast<uint32_t>(start + l) & mask, bits, 0);
    const int64_t dR = tr.update(static_cast<uint32_t>(start + r) & mask, bits, 0);
    integ.add(m.increment(dL, dR));
  }
  return integ.pose();
}

}  // namespace

TEST(EncoderTracker, FirstSampleIsOnlyTheBaseline) {
  EncoderTracker t;
  EncoderTracker::Event e;
  EXPECT_EQ(t.update(12345, 16, 0, &e), 0);
  EXPECT_EQ(e, EncoderTracker::Event::kBaseline);
  EXPECT_EQ(t.update(12400, 16, 0, &e), 55);
  EXPECT_EQ(e, EncoderTracker::Event::kNone);
  EXPECT_EQ(t.update(12300, 16, 0), -100);
}

TEST(EncoderTracker, UnwrapsForwardAndBackwardAcrossTheCounterLimit) {
  EncoderTracker t;
  t.update(65530, 16, 0);
  EXPECT_EQ(t.update(10, 16, 0), 16);    // 65530 -> 65535 -> 0 -> 10
  EXPECT_EQ(t.update(65526, 16, 0), -20);
  EncoderTracker t32;
  t32.update(0xFFFFFFF0u, 32, 0);
  EXPECT_EQ(t32.update(0x10u, 32, 0), 0x20);
  EXPECT_EQ(t32.update(0xFFFFFFF0u, 32, 0), -0x20);
  EncoderTracker t12;  // odd widths too
  t12.update(4090, 12, 0);
  EXPECT_EQ(t12.update(4, 12, 0), 10);
}

TEST(EncoderTracker, BoardResetReBaselinesInsteadOfJumping) {
  EncoderTracker t;
  t.update(30000, 16, 0);
  EXPECT_EQ(t.update(30100, 16, 0), 100);
  EncoderTracker::Event e;
  EXPECT_EQ(t.update(7, 16, 1, &e), 0);  // board rebooted: counter restarted
  EXPECT_EQ(e, EncoderTracker::Event::kBoardReset);
  EXPECT_EQ(t.update(57, 16, 1), 50);
}

TEST(EncoderTracker, BadWidthIsIgnoredAndKeepsTheBaseline) {
  EncoderTracker t;
  t.update(100, 16, 0);
  EncoderTracker::Event e;
  EXPECT_EQ(t.update(5000, 0, 0, &e), 0);
  EXPECT_EQ(e, EncoderTracker::Event::kBadWidth);
  EXPECT_EQ(t.update(150, 16, 0), 50);
  EXPECT_EQ(t.update(5000, 33, 0, &e), 0);
  EXPECT_EQ(e, EncoderTracker::Event::kBadWidth);
}

TEST(WrappedDelta, HalfRangeIsTheLimit) {
  EXPECT_EQ(wrappedDelta(0, 32767, 16), 32767);
  EXPECT_EQ(wrappedDelta(0, 32768, 16), -32768);
}

TEST(Odometry, StraightLine) {
  PoseIntegrator integ;
  const Pose2D p = drive(integ, 2.0, 2.0, 200);
  EXPECT_NEAR(p.x, 2.0, 1e-6);
  EXPECT_NEAR(p.y, 0.0, 1e-9);
  EXPECT_NEAR(p.theta, 0.0, 1e-9);
  EXPECT_NEAR(integ.distance(), 2.0, 1e-6);
}

TEST(Odometry, StraightLineThroughManyWraps) {
  PoseIntegrator integ;
  // 10 m = 200000 ticks through a 16-bit counter: wraps three times; 100 ticks... per sample
  const Pose2D p = drive(integ, 10.0, 10.0, 400, 60000);
  EXPECT_NEAR(p.x, 10.0, 1e-6);
  EXPECT_NEAR(p.y, 0.0, 1e-9);
}

TEST(Odometry, ArcEndsOnTheCircle) {
  // Quarter circle of radius 1 m to the left: left wheel on radius R - b/2, right on R + b/2.
  const double R = 1.0, angle = M_PI / 2;
  PoseIntegrator integ;
  const Pose2D p = drive(integ, (R - kTrack / 2) * angle, (R + kTrack / 2) * angle, 100);
  // Tolerances: one tick is 50 um of wheel travel, 1.7e-4 rad of heading over the track.
  EXPECT_NEAR(p.x, R, 5e-4);
  EXPECT_NEAR(p.y, R, 5e-4);
  EXPECT_NEAR(p.theta, angle, 5e-4);
  // Coarse samples still land on the circle: the integrator follows exact arcs.
  PoseIntegrator coarse;
  const Pose2D q = drive(coarse, (R - kTrack / 2) * angle, (R + kTrack / 2) * angle, 2);
  EXPECT_NEAR(q.x, R, 5e-4);
  EXPECT_NEAR(q.y, R, 5e-4);
}

TEST(Odometry, SpinInPlace) {
  PoseIntegrator integ;
  const double quarter = kTrack / 2 * M_PI / 2;  // each wheel's arc for a quarter turn
  Pose2D p = drive(integ, -quarter, quarter, 50);
  EXPECT_NEAR(p.x, 0.0, 1e-6);
  EXPECT_NEAR(p.y, 0.0, 1e-6);
  EXPECT_NEAR(p.theta, M_PI / 2, 5e-4);
  p = drive(integ, quarter * 2, -quarter * 2, 50);  // half a turn back clockwise
  EXPECT_NEAR(p.theta, -M_PI / 2, 5e-4);
  EXPECT_NEAR(p.x, 0.0, 1e-6);
  p = drive(integ, -quarter * 6, quarter * 6, 50);  // 1.5 turns left: -pi/2 + 3 pi, normalised
  EXPECT_NEAR(p.theta, M_PI / 2, 1e-3);
  EXPECT_NEAR(p.x, 0.0, 1e-6);
}

TEST(Odometry, MirroredEncoderByNegativeScale) {
  WheelPairModel m = model();
  m.left_m_per_tick = -m.left_m_per_tick;  // left encoder counts down going forward
  const OdometryIncrement inc = m.increment(-2000, 2000);
  EXPECT_NEAR(inc.ds, 0.1, 1e-12);
  EXPECT_NEAR(inc.dtheta, 0.0, 1e-12);
}

TEST(Odometry, CovarianceGrowsWithDistance) {
  PoseIntegrator integ;
  drive(integ, 1.0, 1.0, 50);
  const double var_x1 = integ.covariance()(0, 0), var_y1 = integ.covariance()(1, 1), var_t1 = integ.covariance()(2, 2);
  EXPECT_GT(var_x1, 0.0);
  EXPECT_GT(var_t1, 0.0);
  drive(integ, 1.0, 1.0, 50);
  EXPECT_GT(integ.covariance()(0, 0), 1.9 * var_x1);  // random walk along the path
  EXPECT_GT(integ.covariance()(1, 1), 2.0 * var_y1);  // heading error bends the path: grows faster
  EXPECT_GT(integ.covariance()(2, 2), 1.9 * var_t1);
  // Standing still adds nothing.
  const auto before = integ.covariance();
  integ.add(model().increment(0, 0));
  EXPECT_EQ(integ.covariance(), before);
}

TEST(Odometry, FusionWeighsPairsByReliability) {
  IncrementFusion f;
  EXPECT_TRUE(f.empty());
  OdometryIncrement a, b;
  a.ds = 1.0;
  a.var_ds = 1.0;
  b.ds = 2.0;
  b.var_ds = 3.0;
  f.add(a, 0.75);
  f.add(b, 0.25);
  EXPECT_NEAR(f.result().ds, 1.25, 1e-12);
  EXPECT_NEAR(f.result().var_ds, 1.5, 1e-12);
}

TEST(Odometry, FusionIsExactOverTimeWhenPairsSampleAtDifferentMoments) {
  // Pair B lags pair A by one sample: the cumulative fused distance still matches.
  IncrementFusion s1, s2;
  OdometryIncrement a, b, zero;
  a.ds = 0.1;
  b.ds = 0.1;
  s1.add(a, 1.0);
  s1.add(zero, 1.0);
  s2.add(zero, 1.0);  // A saw nothing new
  s2.add(b, 1.0);
  EXPECT_NEAR(s1.result().ds + s2.result().ds, 0.1, 1e-12);
}

// A pair driven straight at constant speed whose right counter always arrives one 20 ms sample
// late (as two boards, or two connections, deliver them): each refresh sees left at sample k
// and right at sample k-1. Returns the pose after 4 m.
Pose2D driveWithSkew(bool aligned) {
  const WheelPairModel m = model();
  const double ticks_per_sample = 0.04 * kTicksPerMeter;  // 2 m/s
  PoseIntegrator integ;
  PairAlignment align;
  double last_l = 0.0, last_r = 0.0;
  for (int k = 1; k <= 101; ++k) {
    const CounterSample l{0.02 * k, ticks_per_sample * std::min(k, 100)};
    const CounterSample r{0.02 * (k - 1), ticks_per_sample * std::min(k - 1, 100)};
    if (aligned) {
      if (auto step = align.advance(l, r)) integ.add(m.increment(step->left_ticks, step->right_ticks));
    } else {
      integ.add(m.increment(l.ticks - last_l, r.ticks - last_r));
    }
    last_l = l.ticks;
    last_r = r.ticks;
  }
  if (aligned) {  // the right side catches up
    if (auto step = align.advance({2.04, 100 * ticks_per_sample}, {2.04, 100 * ticks_per_sample}))
      integ.add(m.increment(step->left_ticks, step->right_ticks));
  } else {
    integ.add(m.increment(100 * ticks_per_sample - last_l, 100 * ticks_per_sample - last_r));
  }
  return integ.pose();
}

TEST(PairAlignment, ASideOneSampleLateIsNotReadAsATurn) {
  const Pose2D naive = driveWithSkew(false);
  EXPECT_NEAR(naive.theta, 0.0, 1e-9);   // the heading comes back once the sides agree...
  EXPECT_GT(std::abs(naive.y), 0.05);    // ...but the drift made meanwhile stays
  const Pose2D aligned = driveWithSkew(true);
  // From the start (left's first sample, where right reaches it). Interpolation assumes a steady
  // speed between samples; the stop inside the last one costs about a millimetre, not 5 cm.
  EXPECT_NEAR(aligned.x, 4.0 - 0.04, 1e-4);
  EXPECT_NEAR(aligned.y, 0.0, 0.002);
  EXPECT_NEAR(aligned.theta, 0.0, 1e-9);
}

TEST(PairAlignment, StartSetsTheCommonInstantAndNoNewerInstantMeansNoStep) {
  PairAlignment a;
  EXPECT_FALSE(a.started());
  EXPECT_FALSE(a.advance({1.0, 100}, {1.0, 200}));
  EXPECT_FALSE(a.started());                        // chosen (1.0 s), but not yet seen reached
  EXPECT_FALSE(a.advance({1.0, 100}, {1.0, 200}));  // both are there: started, no step yet
  EXPECT_TRUE(a.started());
  EXPECT_FALSE(a.advance({1.0, 100}, {1.0, 200}));  // the same samples again
  EXPECT_FALSE(a.advance({1.1, 150}, {1.0, 200}));  // only left moved on: wait for right
  const auto s = a.advance({1.1, 150}, {1.1, 230});
  ASSERT_TRUE(s);
  EXPECT_DOUBLE_EQ(s->stamp, 1.1);
  EXPECT_NEAR(s->dt, 0.1, 1e-12);
  EXPECT_DOUBLE_EQ(s->left_ticks, 50);
  EXPECT_DOUBLE_EQ(s->right_ticks, 30);
  a.restart();
  EXPECT_FALSE(a.advance({5.0, 0}, {5.0, 0}));
  EXPECT_FALSE(a.started());
}

TEST(PairAlignment, TheStartIsTheNewerFirstStampWithTheOlderSideInterpolatedThere) {
  PairAlignment a;
  EXPECT_FALSE(a.advance({0.3, 300}, {0.1, 100}));  // start at 0.3 s; right was at 100 ticks at 0.1 s
  EXPECT_FALSE(a.advance({0.3, 300}, {0.2, 200}));  // right still short of 0.3 s
  EXPECT_FALSE(a.started());
  const auto s = a.advance({0.5, 500}, {0.4, 400});   // right passed 0.3 s: 300 there, started
  ASSERT_TRUE(a.started());
  ASSERT_TRUE(s);
  EXPECT_DOUBLE_EQ(s->stamp, 0.4);
  EXPECT_NEAR(s->left_ticks, 100, 1e-9);
  EXPECT_NEAR(s->right_ticks, 100, 1e-9);
}

TEST(PairAlignment, TheLaterSideIsInterpolatedAndItsRestCountsNextStep) {
  PairAlignment a;
  a.advance({0.0, 0}, {0.0, 0});
  a.advance({0.0, 0}, {0.0, 0});
  // Left has reached 0.3 s (300 ticks), right only 0.1 s (100 ticks): the step ends at 0.1 s.
  auto s = a.advance({0.3, 300}, {0.1, 100});
  ASSERT_TRUE(s);
  EXPECT_DOUBLE_EQ(s->stamp, 0.1);
  EXPECT_NEAR(s->left_ticks, 100, 1e-9);
  EXPECT_NEAR(s->right_ticks, 100, 1e-9);
  s = a.advance({0.3, 300}, {0.3, 300});
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->left_ticks, 200, 1e-9);
  EXPECT_NEAR(s->right_ticks, 200, 1e-9);
}
