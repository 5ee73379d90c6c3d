// Each likelihood of the localization filter, the table model, the motion model and KLD,
// on hand-made particle sets (no ROS).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "hal_nodes/mcl/kld.h"
#include "hal_nodes/mcl/mcl.h"

using namespace hal_nodes::mcl;

namespace {

ParticleSet makeSet(std::initializer_list<Pose2D> poses) {
  ParticleSet s;
  s.resize(poses.size());
  std::size_t i = 0;
  for (const auto& p : poses) {
    s.x[i] = p.x;
    s.y[i] = p.y;
    s.theta[i] = p.theta;
    s.w[i] = 1.0;
    ++i;
  }
  return s;
}

std::shared_ptr<TableModel> table() { return std::make_shared<TableModel>(3.0, 2.1, 0.1, std::vector<Rect>{{1.3, 0.0, 1.7, 0.3}}); }

BeaconBeltsConfig beaconConfig() {
  BeaconBeltsConfig c;
  c.beacons = {{-0.062, -0.062}, {-0.062, 2.162}, {3.062, 1.05}};
  c.range_std = 0.01;
  c.outlier_probability = 0.05;
  return c;
}

double dist(double x, double y, const std::array<double, 2>& b) { return std::hypot(x - b[0], y - b[1]); }

}  // namespace

TEST(TableModel, FreeSpaceHonoursBordersMarginAndObstacles) {
  auto t = table();
  EXPECT_TRUE(t->isFree(1.0, 1.0));
  EXPECT_FALSE(t->isFree(-0.01, 1.0));
  EXPECT_FALSE(t->isFree(0.05, 1.0));   // inside the robot-radius margin
  EXPECT_FALSE(t->isFree(3.05, 1.0));
  EXPECT_FALSE(t->isFree(1.0, 2.2));
  EXPECT_FALSE(t->isFree(1.5, 0.2));    // in the obstacle
  EXPECT_FALSE(t->isFree(1.25, 0.2));   // in the obstacle's margin
  EXPECT_TRUE(t->isFree(1.15, 0.2));
}

TEST(TableModel, CheckMakesImpossibleParticlesWeighZero) {
  auto t = table();
  ParticleSet s = makeSet({{1.0, 1.0, 0}, {-0.5, 1.0, 0}, {1.5, 0.1, 0}, {2.0, 2.5, 0}});
  StepContext ctx;
  t->check(s, ctx);
  EXPECT_EQ(s.w[0], 1.0);
  EXPECT_EQ(s.w[1], 0.0);
  EXPECT_EQ(s.w[2], 0.0);
  EXPECT_EQ(s.w[3], 0.0);
}

TEST(TableModel, ProjectBringsAnEstimateIntoFreeSpace) {
  auto t = table();
  double x = -0.3, y = 1.0;
  t->project(x, y);
  EXPECT_DOUBLE_EQ(x, 0.1);
  EXPECT_DOUBLE_EQ(y, 1.0);
  x = 1.45, y = 0.3;  // in the inflated obstacle, nearest side is x0 - margin = 1.2
  t->project(x, y);
  EXPECT_TRUE(t->isFree(x, y) || std::fabs(x - 1.2) < 1e-9 || std::fabs(y - 0.4) < 1e-9);
  EXPECT_NEAR(y, 0.4, 1e-9);
}

// The table's rays and cones are robot_core's TableGeometry (tested there); the model passes its
// raw blocks on, without the margin.
TEST(TableModel, MeasuresAgainstTheRawBlocks) {
  auto t = table();
  EXPECT_NEAR(t->geometry().rayRange(1.5, 1.0, -M_PI / 2), 0.7, 1e-9);  // the block's top, y = 0.3
  EXPECT_NEAR(t->geometry().distanceToEdge(1.5, 0.5), 0.2, 1e-9);
  EXPECT_FALSE(t->isFree(1.5, 0.35));  // but the robot's centre keeps the margin
}

TEST(TableModel, UniformSamplesAreFree) {
  auto t = table();
  Rng rng(3);
  for (int i = 0; i < 2000; ++i) {
    const Pose2D p = t->sampleFree(rng);
    ASSERT_TRUE(t->isFree(p.x, p.y));
    ASSERT_GE(p.theta, -M_PI);
    ASSERT_LT(p.theta, M_PI);
  }
}

TEST(BeaconBelts, BeltRaisesParticlesAtTheMeasuredRange) {
  auto t = table();
  auto cfg = beaconConfig();
  BeaconBelts b(cfg, t);
  const double r = dist(1.0, 1.0, cfg.beacons[0]);
  ParticleSet s = makeSet({{1.0, 1.0, 0}, {1.02, 1.02, 0}, {1.3, 1.3, 0}, {0.8, 0.8, 0}});
  ASSERT_TRUE(b.addRange(1.0, 0, r));
  StepContext ctx;
  ctx.now = 1.0;
  ctx.quality = 1.0;
  EXPECT_TRUE(b.ready(ctx));
  b.check(s, ctx);
  EXPECT_FALSE(b.ready(ctx));  // consumed
  EXPECT_GT(s.w[0], s.w[1]);
  EXPECT_GT(s.w[1], s.w[2]);
  EXPECT_GT(s.w[2], 0.0);  // far particles are lowered, never killed (outlier term)
  // Symmetric along the belt: another point on the same circle weighs the same.
  ParticleSet s2 = makeSet({{cfg.beacons[0][0] + r, cfg.beacons[0][1], 0}});
  b.addRange(1.0, 0, r);
  b.check(s2, ctx);
  EXPECT_NEAR(s2.w[0], s.w[0], 1e-9 * s.w[0]);
}

TEST(BeaconBelts, LongOutliersAreToleratedMoreThanShortOnes) {
  auto t = table();
  BeaconBelts b(beaconConfig(), t);
  ParticleSet s = makeSet({{1.0, 1.0, 0}});
  ParticleSet s2 = makeSet({{1.0, 1.0, 0}});
  const double r = dist(1.0, 1.0, beaconConfig().beacons[0]);
  StepContext ctx;
  b.addRange(0.0, 0, r + 0.2);  // reflected: too long
  b.check(s, ctx);
  b.addRange(0.0, 0, r - 0.2);  // too short: not a reflection
  b.check(s2, ctx);
  EXPECT_GT(s.w[0], 10.0 * s2.w[0]);
  EXPECT_GT(s2.w[0], 0.0);
}

TEST(BeaconBelts, RejectsUnknownBeaconsAndBadRanges) {
  BeaconBelts b(beaconConfig(), table());
  EXPECT_FALSE(b.addRange(0.0, 7, 1.0));
  EXPECT_FALSE(b.addRange(0.0, 0, -1.0));
  EXPECT_FALSE(b.addRange(0.0, 0, std::nan("")));
  EXPECT_EQ(b.rejected(), 3u);
  StepContext ctx;
  EXPECT_FALSE(b.ready(ctx));
}

TEST(BeaconBelts, IntersectionsWeighMoreOnlyWhenNotConfident) {
  auto t = table();
  auto cfg = beaconConfig();
  cfg.intersection_gain = 4.0;
  BeaconBelts b(cfg, t);
  // Truth (1, 1): belts of beacons 1 and 2 recent; measure beacon 0.
  b.addRange(0.95, 1, dist(1.0, 1.0, cfg.beacons[1]));
  b.addRange(0.97, 2, dist(1.0, 1.0, cfg.beacons[2]));
  // Two particles on beacon 0's belt: at the three-belt intersection, and elsewhere on it.
  const double r0 = dist(1.0, 1.0, cfg.beacons[0]);
  const double a = std::atan2(1.0 - cfg.beacons[0][1], 1.0 - cfg.beacons[0][0]) + 0.3;
  const Pose2D off{cfg.beacons[0][0] + r0 * std::cos(a), cfg.beacons[0][1] + r0 * std::sin(a), 0};
  StepContext ctx;
  ctx.now = 1.0;
  ctx.quality = 0.0;  // lost: intersections count
  ParticleSet s = makeSet({{1.0, 1.0, 0}, off});
  b.addRange(1.0, 0, r0);
  b.check(s, ctx);
  EXPECT_GT(s.w[0], 5.0 * s.w[1]);
  ctx.quality = 1.0;  // confident: the belt alone
  ParticleSet s2 = makeSet({{1.0, 1.0, 0}, off});
  b.addRange(1.0, 0, r0);
  b.check(s2, ctx);
  EXPECT_NEAR(s2.w[0], s2.w[1], 1e-6 * s2.w[0]);
}

TEST(BeaconBelts, TrilaterationProposesThePosition) {
  auto t = table();
  auto cfg = beaconConfig();
  BeaconBelts b(cfg, t);
  StepContext ctx;
  Rng rng(5);
  ctx.rng = &rng;
  ctx.now = 2.0;
  EXPECT_FALSE(b.canSample(ctx));
  b.addRange(1.95, 0, dist(2.2, 0.7, cfg.beacons[0]));
  ctx.now = 1.96;
  EXPECT_FALSE(b.canSample(ctx));  // one belt is not enough
  b.addRange(1.98, 2, dist(2.2, 0.7, cfg.beacons[2]));
  ctx.now = 2.0;
  ASSERT_TRUE(b.canSample(ctx));  // two belts: the point and possibly its mirror image
  b.addRange(1.99, 1, dist(2.2, 0.7, cfg.beacons[1]));
  ctx.now = 2.001;                // the third belt removes the ambiguity
  ASSERT_TRUE(b.canSample(ctx));
  double sx = 0, sy = 0;
  for (int i = 0; i < 200; ++i) {
    const Pose2D p = b.sample(ctx);
    EXPECT_TRUE(t->isFree(p.x, p.y));
    sx += p.x;
    sy += p.y;
  }
  EXPECT_NEAR(sx / 200, 2.2, 0.03);
  EXPECT_NEAR(sy / 200, 0.7, 0.03);
  ctx.now = 3.0;  // ranges too old
  EXPECT_FALSE(b.canSample(ctx));
}

TEST(BeaconBelts, ReliabilityZeroIgnoresTheMeasurement) {
  auto cfg = beaconConfig();
  cfg.reliability = 0.0;
  BeaconBelts b(cfg, table());
  ParticleSet s = makeSet({{1.0, 1.0, 0}, {2.0, 1.5, 0}});
  StepContext ctx;
  b.addRange(0.0, 0, 1.0);
  b.check(s, ctx);
  EXPECT_DOUBLE_EQ(s.w[0], 1.0);
  EXPECT_DOUBLE_EQ(s.w[1], 1.0);
}

TEST(Compass, PeaksAtTheHeadingAndWrapsAroundPi) {
  CompassConfig cfg;
  cfg.reliability = 1.0;
  Compass c(cfg);
  ASSERT_TRUE(c.addHeading(0.0, M_PI - 0.01));
  EXPECT_GT(c.likelihood(M_PI - 0.01), c.likelihood(M_PI - 0.1));
  EXPECT_NEAR(c.likelihood(-M_PI + 0.01), c.likelihood(M_PI - 0.03), 1e-9);  // across the wrap
  EXPECT_GT(c.likelihood(0.0), 0.0);                                            // outlier floor
  ParticleSet s = makeSet({{1, 1, M_PI - 0.01}, {1, 1, 0.0}});
  StepContext ctx;
  c.check(s, ctx);
  EXPECT_GT(s.w[0], 100.0 * s.w[1]);
  EXPECT_FALSE(c.addHeading(0.0, std::nan("")));
}

TEST(Rangers, ReadingAgainstTheTableBorder) {
  auto t = table();
  RangerConfig front;
  front.name = "front";
  front.x = 0.1;  // 10 cm ahead of the centre, facing forward
  front.max_range = 2.0;
  Rangers r({front}, 1.0, t);
  // Robot at x = 2.3 facing +x: the ranger is at 2.4, border at 3.0: expected 0.6.
  EXPECT_GT(r.likelihood(0, {2.3, 1.0, 0.0}, 0.6), 10.0 * r.likelihood(0, {2.0, 1.0, 0.0}, 0.6));
  // Max-range reading: fits poses far from the border, not poses near it.
  EXPECT_GT(r.likelihood(0, {0.3, 1.0, 0.0}, 2.0), r.likelihood(0, {2.3, 1.0, 0.0}, 2.0));
  ParticleSet s = makeSet({{2.3, 1.0, 0.0}, {2.0, 1.0, 0.0}});
  StepContext ctx;
  ASSERT_TRUE(r.addRange(r.index("front"), 0.0, 0.6));
  EXPECT_TRUE(r.ready(ctx));
  r.check(s, ctx);
  EXPECT_FALSE(r.ready(ctx));
  EXPECT_GT(s.w[0], s.w[1]);
  // +inf (REP 117, nothing in range, as the HAL's filter passes it on) is that reading.
  ParticleSet inf = makeSet({{0.3, 1.0, 0.0}, {2.3, 1.0, 0.0}});
  ASSERT_TRUE(r.addRange(r.index("front"), 5.0, std::numeric_limits<double>::infinity()));
  r.check(inf, StepContext());
  EXPECT_GT(inf.w[0], 2.0 * inf.w[1]);
  EXPECT_THROW(r.index("nope"), std::out_of_range);
}

TEST(Rangers, AMinimumRangeReadingMeansThisNearOrNearer) {
  auto t = table();
  RangerConfig back;
  back.name = "back";
  back.yaw = M_PI;  // at the centre, looking backwards
  back.min_range = 0.16;  // an SRF02: 16 cm for anything nearer
  back.std = 0.03;
  Rangers r({back}, 1.0, t);
  // The robot 8 cm from the x = 0 border reads 0.16: as likely as 12 cm away (both "nearer"),
  // far more than 20 cm away, where a border would have been seen beyond the minimum.
  EXPECT_NEAR(r.likelihood(0, {0.08, 1.0, 0.0}, 0.16), r.likelihood(0, {0.04, 1.0, 0.0}, 0.16), 0.01);
  EXPECT_GT(r.likelihood(0, {0.08, 1.0, 0.0}, 0.16), 0.75);  // (1 - short) * ~1
  EXPECT_GT(r.likelihood(0, {0.08, 1.0, 0.0}, 0.16), 10.0 * r.likelihood(0, {0.26, 1.0, 0.0}, 0.16));
  // Taken as an exact 0.16 it would have favoured 16 cm over the true 8 cm.
  ParticleSet s = makeSet({{0.08, 1.0, 0.0}, {0.16, 1.0, 0.0}});
  StepContext ctx;
  ASSERT_TRUE(r.addRange(0, 0.0, 0.16));
  r.check(s, ctx);
  EXPECT_GT(s.w[0], 1.5 * s.w[1]);
  // REP 117's -inf ("too near to measure") is the same reading; NaN is refused.
  ParticleSet n = makeSet({{0.08, 1.0, 0.0}, {0.16, 1.0, 0.0}});
  ASSERT_TRUE(r.addRange(0, 1.0, -std::numeric_limits<double>::infinity()));
  r.check(n, ctx);
  EXPECT_DOUBLE_EQ(n.w[0] / n.w[1], s.w[0] / s.w[1]);
  EXPECT_FALSE(r.addRange(0, 2.0, std::nan("")));
  // Above the minimum, a reading is a distance again.
  EXPECT_GT(r.likelihood(0, {0.30, 1.0, 0.0}, 0.30), 10.0 * r.likelihood(0, {0.08, 1.0, 0.0}, 0.30));
}

TEST(Rangers, ASonarIsMeasuredOverItsCone) {
  auto t = table();
  RangerConfig side;
  side.name = "front_left";
  side.yaw = M_PI / 4;  // at the centre, looking 45 deg to the left
  side.max_range = 2.0;
  Rangers from_reading({side}, 1.0, t);
  const double echo = 0.5 / std::sin(M_PI / 4 + 0.48);  // the nearest echo in a 0.96 rad cone
  const Pose2D truth{1.0, 1.6, 0.0};
  EXPECT_GT(from_reading.likelihood(0, truth, echo, 0.96), 10.0 * from_reading.likelihood(0, truth, echo, 0.0));
  // beam_width < 0: each reading's field_of_view; the pose the echo fits gains weight.
  ParticleSet s = makeSet({{1.0, 1.6, 0.0}, {1.0, 2.1 - echo * std::sin(M_PI / 4), 0.0}});
  StepContext ctx;
  ASSERT_TRUE(from_reading.addRange(0, 0.0, echo, 0.96));
  from_reading.check(s, ctx);
  EXPECT_GT(s.w[0], 10.0 * s.w[1]);
  // A configured beam_width overrides the reading's.
  side.beam_width = 0.0;
  Rangers centre_line({side}, 1.0, t);
  ParticleSet c = makeSet({{1.0, 1.6, 0.0}, {1.0, 2.1 - echo * std::sin(M_PI / 4), 0.0}});
  ASSERT_TRUE(centre_line.addRange(0, 0.0, echo, 0.96));
  centre_line.check(c, ctx);
  EXPECT_GT(c.w[1], 10.0 * c.w[0]);
}

TEST(Bumpers, ClosedBumperMeansABorderIsNear) {
  auto t = table();
  BumpersOptions opts;
  opts.reliability = 1.0;
  Bumpers b({{"front", 0.15, 0.0}, {"rear", -0.15, 0.0}}, opts, t);
  StepContext ctx;
  EXPECT_FALSE(b.ready(ctx));  // nothing closed: no information
  b.setClosed(0.0, {"front", "ghost"});
  EXPECT_EQ(b.unknown(), 1u);
  EXPECT_TRUE(b.ready(ctx));
  EXPECT_GT(b.likelihood({2.85, 1.0, 0.0}), 2.0 * b.likelihood({1.5, 1.0, 0.0}));  // front touches x = 3
  ParticleSet s = makeSet({{2.85, 1.0, 0.0}, {1.5, 1.0, 0.0}});
  b.check(s, ctx);
  EXPECT_GT(s.w[0], s.w[1]);
  EXPECT_GT(s.w[1], 0.0);  // may be pushing the opponent
}

TEST(MotionModel, NoiselessIncrementIsExactAndNoiseIsCentred) {
  MotionModel quiet{0, 0, 0, 0, 0, 0, 0, 0};
  ParticleSet s = makeSet({{1.0, 1.0, M_PI / 2}});
  Rng rng(1);
  quiet.apply(s, {0.1, 0.0, 0.0}, rng);
  EXPECT_NEAR(s.x[0], 1.0, 1e-12);
  EXPECT_NEAR(s.y[0], 1.1, 1e-12);
  MotionModel noisy;
  noisy.slip_probability = 0.0;
  ParticleSet many;
  many.resize(4000);
  for (std::size_t i = 0; i < many.size(); ++i) many.x[i] = many.y[i] = many.theta[i] = 0.0;
  noisy.apply(many, {0.1, 0.0, 0.0}, rng);
  double mx = 0, vt = 0;
  for (std::size_t i = 0; i < many.size(); ++i) {
    mx += many.x[i];
    vt += many.theta[i] * many.theta[i];
  }
  EXPECT_NEAR(mx / many.size(), 0.1, 0.001);
  EXPECT_NEAR(std::sqrt(vt / many.size()), noisy.rot_per_trans * 0.1, 0.003);
}

TEST(MotionModel, SlipsOnlyShortenTheTravel) {
  MotionModel slip{0, 0, 0, 0, 0, 1.0, 0.01, 0.0};
  ParticleSet s;
  s.resize(500);
  for (std::size_t i = 0; i < s.size(); ++i) s.x[i] = s.y[i] = s.theta[i] = 0.0;
  Rng rng(2);
  slip.apply(s, {0.05, 0.0, 0.0}, rng);
  for (std::size_t i = 0; i < s.size(); ++i) ASSERT_LE(s.x[i], 0.05 + 1e-12);
  MotionModel bad;
  bad.slip_probability = 2.0;
  EXPECT_THROW(bad.validate(), std::invalid_argument);
}

TEST(OdometryInput, PairsAreAveragedByReliability) {
  OdometryInput odo({{"drive", 0.25}, {"idle", 0.75}}, MotionModel{0, 0, 0, 0, 0, 0, 0, 0});
  odo.addIncrement(odo.pairIndex("drive"), {0.04, 0.0, 0.0});
  odo.addIncrement(odo.pairIndex("idle"), {0.08, 0.0, 0.0});
  EXPECT_NEAR(odo.pending().x, 0.07, 1e-12);
  ParticleSet s = makeSet({{0, 0, 0}});
  Rng rng(1);
  StepContext ctx;
  ctx.rng = &rng;
  odo.advance(s, ctx);
  EXPECT_NEAR(s.x[0], 0.07, 1e-12);
  EXPECT_NEAR(odo.pending().x, 0.0, 1e-12);  // consumed
  // Poses: the first sets the reference, the next gives the increment in the robot frame.
  odo.addPose(0, {1.0, 1.0, M_PI / 2});
  odo.addPose(0, {1.0, 1.2, M_PI / 2});
  EXPECT_NEAR(odo.pending().x, 0.2, 1e-12);  // only "drive" moved: it alone votes
  EXPECT_THROW(odo.pairIndex("none"), std::out_of_range);
}

// 0.5 m/s at 100 Hz, stamped, with a quiet motion model (slip detection on by default).
void feedSteady(OdometryInput& odo, std::size_t pair, double from, int steps, double speed = 0.5) {
  for (int k = 1; k <= steps; ++k) odo.addIncrement(pair, {speed * 0.01, 0.0, 0.0}, from + 0.01 * k);
}

TEST(OdometryInput, TravelTheRobotCannotHaveMadeIsASlip) {
  OdometryInput odo({{"wheels", 1.0}}, MotionModel{0, 0, 0, 0, 0, 0, 0, 0});
  ParticleSet s = makeSet({{0, 0, 0}});
  Rng rng(1);
  StepContext ctx;
  ctx.rng = &rng;
  feedSteady(odo, 0, 0.0, 10);
  odo.advance(s, ctx);
  EXPECT_NEAR(s.x[0], 0.05, 1e-12);
  EXPECT_EQ(odo.slips(), 0u);
  // A wheel spins: 8 mm more in 10 ms than 5 mm at 0.5 m/s (a 0.8 m/s jump; 5 m/s^2 allows 0.05).
  odo.addIncrement(0, {0.013, 0.0, 0.0}, 0.11);
  EXPECT_EQ(odo.slips(), 1u);
  EXPECT_NEAR(odo.pending().x, 0.005, 1e-12);  // the robot went on at its speed
  odo.advance(s, ctx);
  // Back to normal, and what the robot can do is still accepted: 0.5 -> 0.54 m/s in 10 ms.
  odo.addIncrement(0, {0.005, 0.0, 0.0}, 0.12);
  odo.addIncrement(0, {0.0054, 0.0, 0.0}, 0.13);
  EXPECT_EQ(odo.slips(), 1u);
  // Stopping dead (a collision) is what the robot did, not a slip.
  odo.addIncrement(0, {0.0, 0.0, 0.0}, 0.14);
  EXPECT_EQ(odo.slips(), 1u);
  odo.advance(s, ctx);
  EXPECT_NEAR(s.x[0], 0.05 + 0.005 + 0.005 + 0.0054, 1e-12);
  // Backwards the same: a spin is too much travel either way.
  OdometryInput back({{"wheels", 1.0}}, MotionModel{0, 0, 0, 0, 0, 0, 0, 0});
  feedSteady(back, 0, 0.0, 5, -0.5);
  back.addIncrement(0, {-0.02, 0.0, 0.0}, 0.06);
  EXPECT_EQ(back.slips(), 1u);
  EXPECT_NEAR(back.pending().x, -0.03, 1e-12);  // 5 x -5 mm, then -5 mm instead of -20
  // A robot really pushed from rest to 1 m/s is followed again once it can have got there
  // (5 m/s^2: 0.2 s), not held at rest.
  OdometryInput pushed({{"wheels", 1.0}}, MotionModel{0, 0, 0, 0, 0, 0, 0, 0});
  feedSteady(pushed, 0, 0.0, 5, 0.0);
  feedSteady(pushed, 0, 0.05, 30, 1.0);
  const std::size_t slipping = pushed.slips();
  EXPECT_GE(slipping, 15u);
  EXPECT_LE(slipping, 22u);
  feedSteady(pushed, 0, 0.35, 10, 1.0);
  EXPECT_EQ(pushed.slips(), slipping);
  // Stamped on reception: one increment 8 ms late, the next 2 ms after it, each with 10 ms
  // of travel at 1 m/s. Neither is a slip.
  const double before = pushed.pending().x;
  pushed.addIncrement(0, {0.01, 0.0, 0.0}, 0.468);
  pushed.addIncrement(0, {0.01, 0.0, 0.0}, 0.470);
  EXPECT_EQ(pushed.slips(), slipping);
  EXPECT_NEAR(pushed.pending().x - before, 0.02, 1e-9);
}

TEST(OdometryInput, NoSlipDetectionWithoutStampsOrWhenDisabled) {
  OdometryInput unstamped({{"wheels", 1.0}}, MotionModel{0, 0, 0, 0, 0, 0, 0, 0});
  for (int k = 0; k < 10; ++k) unstamped.addIncrement(0, {0.005, 0.0, 0.0});
  unstamped.addIncrement(0, {0.013, 0.0, 0.0});
  EXPECT_EQ(unstamped.slips(), 0u);
  MotionModel off{0, 0, 0, 0, 0, 0, 0, 0};
  off.slip_accel = 0.0;
  OdometryInput disabled({{"wheels", 1.0}}, off);
  feedSteady(disabled, 0, 0.0, 10);
  disabled.addIncrement(0, {0.013, 0.0, 0.0}, 0.11);
  EXPECT_EQ(disabled.slips(), 0u);
  EXPECT_NEAR(disabled.pending().x, 0.063, 1e-12);
  MotionModel bad;
  bad.slip_margin = -0.001;
  EXPECT_THROW(bad.validate(), std::invalid_argument);
}

TEST(OdometryInput, ASlippingPairIsOutvotedAndASlipSpreadsEveryHeading) {
  MotionModel m{0, 0, 0, 0, 0, 0, 0, 0.02};  // only the slip's heading noise
  OdometryInput odo({{"drive", 1.0}, {"idle", 0.5}}, m);
  const std::size_t drive = odo.pairIndex("drive"), idle = odo.pairIndex("idle");
  feedSteady(odo, drive, 0.0, 10);
  feedSteady(odo, idle, 0.0, 10);
  ParticleSet s;
  s.resize(2000);
  for (std::size_t i = 0; i < s.size(); ++i) s.x[i] = s.y[i] = s.theta[i] = 0.0;
  Rng rng(3);
  StepContext ctx;
  ctx.rng = &rng;
  odo.advance(s, ctx);
  for (std::size_t i = 0; i < s.size(); ++i) ASSERT_EQ(s.theta[i], 0.0);  // no slip, no noise
  // The driven wheels spin, the measuring pair does not: it alone votes, no slip noise.
  odo.addIncrement(drive, {0.02, 0.0, 0.0}, 0.11);
  odo.addIncrement(idle, {0.0051, 0.0, 0.0}, 0.11);
  EXPECT_NEAR(odo.pending().x, 0.0051, 1e-12);
  odo.advance(s, ctx);
  for (std::size_t i = 0; i < s.size(); ++i) ASSERT_EQ(s.theta[i], 0.0);
  // Both slip: every particle's heading spreads by slip_rot.
  odo.addIncrement(drive, {0.02, 0.0, 0.0}, 0.12);
  odo.addIncrement(idle, {0.02, 0.0, 0.0}, 0.12);
  odo.advance(s, ctx);
  double var = 0.0;
  std::size_t moved = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    var += s.theta[i] * s.theta[i];
    moved += s.theta[i] != 0.0;
  }
  EXPECT_EQ(moved, s.size());
  EXPECT_NEAR(std::sqrt(var / s.size()), 0.02, 0.002);
}

TEST(Kld, BoundGrowsWithOccupiedBins) {
  KldParams p;
  EXPECT_LT(kldBound(2, p), kldBound(20, p));
  EXPECT_LT(kldBound(20, p), kldBound(200, p));
  BinCounter bins(100);
  EXPECT_EQ(bins.add(0.001, 0.001, 0.001, p), 1u);
  EXPECT_EQ(bins.add(0.002, 0.002, 0.002, p), 1u);  // same bin
  EXPECT_EQ(bins.add(0.5, 0.002, 0.002, p), 2u);
  EXPECT_EQ(bins.add(-0.5, -0.002, -3.0, p), 3u);
  bins.clear();
  EXPECT_EQ(bins.count(), 0u);
}
