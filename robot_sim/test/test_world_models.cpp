// Unit tests of the world's models: kinematics, motor, slip, rangers, compass, beacons,
// actuators, fault schedule and the configuration reader.
#include <gtest/gtest.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <cmath>
#include <vector>

#include "robot_sim/world/actuators.h"
#include "robot_sim/world/beacon_model.h"
#include "robot_sim/world/compass_model.h"
#include "robot_sim/world/config.h"
#include "robot_sim/world/diff_drive.h"
#include "robot_sim/world/fault_schedule.h"
#include "robot_sim/world/motor_model.h"
#include "robot_sim/world/ranger_model.h"

using namespace robot_sim;

namespace {
struct Stats {
  double n = 0, sum = 0, sq = 0;
  void add(double x) {
    ++n;
    sum += x;
    sq += x * x;
  }
  double mean() const { return sum / n; }
  double std() const { return std::sqrt(std::max(0.0, sq / n - mean() * mean())); }
};
}  // namespace

TEST(Kinematics, StraightAndArcIntegrateExactly) {
  Pose2D p{0.5, 0.5, M_PI / 2};
  for (int i = 0; i < 2000; ++i) p = integrateTwist(p, 0.5, 0.0, 0.001);
  EXPECT_NEAR(p.x, 0.5, 1e-9);
  EXPECT_NEAR(p.y, 1.5, 1e-9);
  // A full circle of radius 0.4 comes back to its start.
  Pose2D q{1.0, 1.0, 0.0};
  const double w = 0.5, v = 0.2, T = 2 * M_PI / w;
  const int n = 10000;
  for (int i = 0; i < n; ++i) q = integrateTwist(q, v, w, T / n);
  EXPECT_NEAR(q.x, 1.0, 1e-6);
  EXPECT_NEAR(q.y, 1.0, 1e-6);
  EXPECT_NEAR(wrapAngle(q.theta), 0.0, 1e-6);
  // A quarter circle to the left ends at (r, r) from the start.
  Pose2D h{0.0, 0.0, 0.0};
  for (int i = 0; i < n; ++i) h = integrateTwist(h, v, w, T / 4 / n);
  EXPECT_NEAR(h.x, 0.4, 1e-6);
  EXPECT_NEAR(h.y, 0.4, 1e-6);
}

TEST(Kinematics, WheelsToTwist) {
  double v, w;
  wheelsToTwist(0.2, 0.4, 0.25, v, w);
  EXPECT_DOUBLE_EQ(v, 0.3);
  EXPECT_DOUBLE_EQ(w, 0.8);
}

TEST(Motor, FirstOrderLagAccelAndCurrentLimits) {
  MotorConfig c;
  c.max_speed = 20.0;
  c.time_constant = 0.1;
  c.max_accel = 1000.0;   // not limiting here
  c.stall_current = 5.0;
  c.current_limit = 100.0;  // not limiting here
  MotorState s;
  s.command = 0.5;
  for (int i = 0; i < 100; ++i) stepMotor(c, s, 0.001);  // one time constant
  EXPECT_NEAR(s.speed, 10.0 * (1 - std::exp(-1.0)), 1e-6);
  for (int i = 0; i < 2000; ++i) stepMotor(c, s, 0.001);
  EXPECT_NEAR(s.speed, 10.0, 1e-6);

  // Acceleration bound.
  c.max_accel = 20.0;
  MotorState a;
  a.command = 1.0;
  for (int i = 0; i < 100; ++i) {
    stepMotor(c, a, 0.001);
    EXPECT_LE(a.accel, 20.0 + 1e-9);
  }
  EXPECT_NEAR(a.speed, 2.0, 1e-9);

  // Current limit: a full command from rest never draws more than the limit and is slower.
  c.max_accel = 1000.0;
  c.current_limit = 2.0;
  c.no_load_current = 0.0;
  MotorState l, u;
  l.command = u.command = 1.0;
  MotorConfig unlimited = c;
  unlimited.current_limit = 100.0;
  for (int i = 0; i < 50; ++i) {
    stepMotor(c, l, 0.001);
    stepMotor(unlimited, u, 0.001);
    EXPECT_LE(std::abs(l.current), 2.0 + 1e-9);
  }
  EXPECT_LT(l.speed, u.speed);
  EXPECT_GT(u.current, 2.0);

  // Blocked shaft: zero speed, stall current clipped at the limit.
  stepMotor(c, l, 0.001, true);
  EXPECT_EQ(l.speed, 0.0);
  EXPECT_NEAR(l.current, 2.0, 1e-9);

  // Inverted: a positive command turns the wheel backwards.
  MotorConfig inv = c;
  inv.inverted = true;
  MotorState i;
  i.command = 0.5;
  stepMotor(inv, i, 0.01);
  EXPECT_LT(i.speed, 0.0);
}

TEST(Motor, DeadBandHoldsSmallCommandsAndSpansTheRest) {
  MotorConfig c;
  c.max_speed = 20.0;
  c.time_constant = 0.01;
  c.max_accel = 1e6;
  c.current_limit = 100.0;
  c.dead_band = 0.1;
  MotorState s;
  s.command = 0.08;  // inside the band: friction wins
  for (int i = 0; i < 1000; ++i) stepMotor(c, s, 0.001);
  EXPECT_NEAR(s.speed, 0.0, 1e-9);
  s.command = -0.55;  // halfway through what is left of the range
  for (int i = 0; i < 1000; ++i) stepMotor(c, s, 0.001);
  EXPECT_NEAR(s.speed, -10.0, 1e-6);
  s.command = 1.0;
  for (int i = 0; i < 1000; ++i) stepMotor(c, s, 0.001);
  EXPECT_NEAR(s.speed, 20.0, 1e-6);
}

TEST(Slip, MeanGrowsWithAccelerationAndNoiseMatches) {
  SlipConfig c;
  c.per_accel = 0.02;
  c.noise_std = 0.01;
  c.max = 0.9;
  Rng rng(3, "slip");
  for (double accel : {0.0, 1.0, 3.0, -2.0}) {
    Stats s;
    for (int i = 0; i < 200000; ++i) s.add(slipFraction(c, 0.4, accel, 0.0, rng));
    EXPECT_NEAR(s.mean(), 0.02 * accel, 5e-4) << "accel " << accel;
    EXPECT_NEAR(s.std(), 0.01, 5e-4) << "accel " << accel;
  }
  // Backwards driving: speeding up backwards is still positive slip.
  Stats b;
  for (int i = 0; i < 100000; ++i) b.add(slipFraction(c, -0.4, -2.0, 0.0, rng));
  EXPECT_NEAR(b.mean(), 0.04, 5e-4);
  // A standing wheel does not slip; an injected hard slip adds on top.
  EXPECT_EQ(slipFraction(c, 0.0, 5.0, 0.0, rng), 0.0);
  c.noise_std = 0.0;
  EXPECT_NEAR(slipFraction(c, 0.4, 0.0, 0.6, rng), 0.6, 1e-12);
}

TEST(Ranger, SeesBordersAndOpponentWithinTheBeam) {
  TableGeometry table(3.0, 2.1);
  RangerConfig srf;
  srf.beam_width = 0.5;
  srf.max_range = 6.0;
  srf.mount = Pose2D{0.1, 0.0, 0.0};
  // Facing +x from x=1 (sensor at 1.1): the border at x=3 is 1.9 m ahead (the cone's central ray).
  const Pose2D robot{1.0, 1.05, 0.0};
  EXPECT_NEAR(trueRange(srf, robot, table, {}), 1.9, 1e-9);
  // An opponent straight ahead is seen at its near surface.
  EXPECT_NEAR(trueRange(srf, robot, table, {Circle{2.0, 1.05, 0.15}}), 0.75, 1e-9);
  // Off to the side by 0.3 m: inside the 0.5 rad cone of the SRF02 ...
  const double seen = trueRange(srf, robot, table, {Circle{2.0, 1.35, 0.15}});
  EXPECT_LT(seen, 1.0);
  // ... but not in the narrow SHARP beam, which also sees nothing beyond its 0.8 m.
  RangerConfig sharp = srf;
  sharp.type = "sharp";
  sharp.beam_width = 0.06;
  sharp.max_range = 0.8;
  EXPECT_TRUE(std::isinf(trueRange(sharp, robot, table, {Circle{2.0, 1.35, 0.15}})));
  EXPECT_NEAR(trueRange(sharp, robot, table, {Circle{1.6, 1.05, 0.15}}), 0.35, 1e-9);
}

TEST(Ranger, NoiseStatisticsMatchConfig) {
  RangerConfig r;
  r.noise_std = 0.01;
  r.noise_rel = 0.02;
  r.min_range = 0.03;
  r.max_range = 6.0;
  Rng rng(5, "ranger");
  Stats s;
  for (int i = 0; i < 100000; ++i) s.add(noisyRange(r, 1.5, rng));
  EXPECT_NEAR(s.mean(), 1.5, 5e-4);
  EXPECT_NEAR(s.std(), 0.01 + 0.02 * 1.5, 1e-3);
  EXPECT_TRUE(std::isinf(noisyRange(r, std::numeric_limits<double>::infinity(), rng)));
  EXPECT_GE(noisyRange(r, 0.0, rng), 0.03);

  r.bias = 0.02;  // a sensor that reads long by 2 cm
  Stats b;
  for (int i = 0; i < 100000; ++i) b.add(noisyRange(r, 1.5, rng));
  EXPECT_NEAR(b.mean(), 1.52, 5e-4);
}

TEST(Compass, HeadingBiasAndNoise) {
  CompassConfig c;
  c.north_deg = 90.0;
  c.bias_deg = 3.0;
  c.noise_std_deg = 0.5;
  EXPECT_NEAR(trueCompassDeg(c, M_PI / 2), 0.0, 1e-9);   // facing north
  EXPECT_NEAR(trueCompassDeg(c, 0.0), 90.0, 1e-9);       // east is clockwise of north
  EXPECT_NEAR(trueCompassDeg(c, M_PI), 270.0, 1e-9);
  Rng rng(7, "compass");
  Stats s;
  for (int i = 0; i < 100000; ++i) s.add(noisyCompassDeg(c, 0.0, rng));
  EXPECT_NEAR(s.mean(), 93.0, 0.01);
  EXPECT_NEAR(s.std(), 0.5, 0.01);
}

TEST(Beacons, SlotsNoiseDropoutsOutliersAndSilence) {
  BeaconConfig c;
  c.period = 0.15;
  c.noise_std = 20e-6;
  c.dropout = 0.1;
  c.outlier = 0.05;
  c.max_delta = 0.02;
  const std::vector<Point2D> beacons = {{-0.062, -0.062}, {-0.062, 2.162}, {3.062, 1.05}};
  BeaconModel model(c, beacons);
  Rng rng(11, "beacons");
  const Pose2D robot{1.0, 0.8, 0.3};
  const int steps = 300000;  // 300 s at 1 ms: 2000 cycles
  std::vector<BeaconMeasurement> all;
  for (int k = 1; k <= steps; ++k) {
    model.step(k * 0.001, robot, rng);
    if (k % 100 == 0)
      for (auto& m : model.take()) all.push_back(m);
  }
  const double slots = std::floor(300.0 / (0.15 / 3)) + 1;
  EXPECT_NEAR(all.size() / slots, 1.0 - 0.1, 0.01);  // dropouts
  int outliers = 0;
  Stats err;
  int per_id[3] = {0, 0, 0};
  for (const auto& m : all) {
    ++per_id[m.beacon_id];
    const double e = m.delta_s - model.trueDelta(m.beacon_id, robot.x, robot.y);
    if (std::abs(e) > 10 * 20e-6) ++outliers;
    else err.add(e);
    // Slot timing: beacon i transmits at (k*3 + i) * period/3.
    const double slot = m.stamp / 0.05;
    EXPECT_NEAR(slot, std::round(slot), 1e-6);
    EXPECT_EQ(static_cast<long>(std::lround(slot)) % 3, m.beacon_id);
  }
  EXPECT_NEAR(outliers / static_cast<double>(all.size()), 0.05, 0.01);
  EXPECT_NEAR(err.mean(), 0.0, 2e-6);
  EXPECT_NEAR(err.std(), 20e-6, 1.5e-6);
  EXPECT_GT(per_id[0], 0);
  EXPECT_GT(per_id[2], 0);

  model.setSilent(1, true);
  for (int k = steps + 1; k <= steps + 3000; ++k) model.step(k * 0.001, robot, rng);
  for (const auto& m : model.take()) EXPECT_NE(m.beacon_id, 1);
}

TEST(Actuators, ServoSlewsAndStepperSteps) {
  ServoConfig sc;
  sc.min = -1.0;
  sc.max = 1.0;
  sc.speed = 2.0;
  ServoState s{5.0, 0.0};  // target beyond travel: clamped to max
  for (int i = 0; i < 250; ++i) stepServo(sc, s, 0.001);
  EXPECT_NEAR(s.position, 0.5, 1e-9);
  for (int i = 0; i < 1000; ++i) stepServo(sc, s, 0.001);
  EXPECT_NEAR(s.position, 1.0, 1e-9);

  StepperConfig st;
  st.min = 0;
  st.max = 1000;
  st.steps_per_second = 500;
  StepperState p{800, 0, 0.0};
  for (int i = 0; i < 1000; ++i) stepStepper(st, p, 0.001);
  EXPECT_EQ(p.position, 500);
  for (int i = 0; i < 1000; ++i) stepStepper(st, p, 0.001);
  EXPECT_EQ(p.position, 800);
}

TEST(Faults, ScheduleStartsEndsAndClears) {
  FaultSchedule f;
  f.add(FaultEntry{"wheel_slip", "left", 1.0, 1.5, 0.0, false});
  f.add(FaultEntry{"board_silent", "motor_board", 2.0, 0.0, 0.0, false});
  EXPECT_TRUE(f.update(0.9).empty());
  auto t = f.update(1.0);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_TRUE(t[0].activate);
  EXPECT_EQ(t[0].fault.kind, "wheel_slip");
  EXPECT_EQ(f.active().size(), 1u);
  t = f.update(1.5);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_FALSE(t[0].activate);
  t = f.update(2.0);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].fault.target, "motor_board");
  EXPECT_TRUE(f.update(100.0).empty());  // open-ended
  EXPECT_TRUE(f.clear("board_silent", "motor_board"));
  t = f.update(100.1);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_FALSE(t[0].activate);
  EXPECT_TRUE(f.empty());
}

// The simulated robot is the robot as described (/robot): outline radius, wheels, the driven
// encoders' resolution and each ranger's mount from its link; a value of its own wins.
TEST(Config, TheSimulatedRobotTakesItsGeometryFromTheDescription) {
  XmlRpc::XmlRpcValue world, table, robot;
  world["robot"]["motors"]["left"]["drive"] = std::string("left");
  world["robot"]["motors"]["right"]["drive"] = std::string("right");
  world["robot"]["motors"]["lift"]["max_speed"] = 5.0;
  world["robot"]["encoders"]["left_driven"]["motor"] = std::string("left");
  world["robot"]["encoders"]["lift"]["motor"] = std::string("lift");
  world["robot"]["rangers"]["front"]["type"] = std::string("srf02");
  robot["radius"] = 0.21;
  robot["wheel_radius"] = 0.041;
  robot["track_width"] = 0.31;
  robot["encoder_ticks_per_rev"] = 400;
  XmlRpc::XmlRpcValue at;
  for (int i = 0; i < 6; ++i) at[i] = std::vector<double>{0.12, -0.03, 0.1, 0.0, 0.0, 0.5}[i];
  robot["links"]["ranger_front"]["at"] = at;
  WorldConfig c = parseWorldConfig(world, "/sim/world", table, "/table", robot, "/robot");
  EXPECT_DOUBLE_EQ(c.robot.radius, 0.21);
  EXPECT_DOUBLE_EQ(c.robot.wheel_radius, 0.041);
  EXPECT_DOUBLE_EQ(c.robot.wheel_base, 0.31);
  EXPECT_EQ(c.robot.encoders.at("left_driven").ticks_per_rev, 400);
  EXPECT_EQ(c.robot.encoders.at("lift").ticks_per_rev, 512);  // not a driven wheel: its own default
  EXPECT_DOUBLE_EQ(c.robot.rangers.at("front").mount.x, 0.12);
  EXPECT_DOUBLE_EQ(c.robot.rangers.at("front").mount.y, -0.03);
  EXPECT_DOUBLE_EQ(c.robot.rangers.at("front").mount.theta, 0.5);

  world["robot"]["wheel_base"] = 0.32;  // a simulated robot that differs on purpose
  c = parseWorldConfig(world, "/sim/world", table, "/table", robot, "/robot");
  EXPECT_DOUBLE_EQ(c.robot.wheel_base, 0.32);

  robot["wheel_radius"] = -0.04;
  try {
    parseWorldConfig(world, "/sim/world", table, "/table", robot, "/robot");
    FAIL() << "a negative described wheel radius accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/robot/wheel_radius"), std::string::npos) << e.what();
  }
  robot["wheel_radius"] = 0.04;
  robot["links"]["ranger_front"]["parent"] = std::string("camera_link");
  try {
    parseWorldConfig(world, "/sim/world", table, "/table", robot, "/robot");
    FAIL() << "a ranger hung on another link taken as mounted on base_link";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/robot/links/ranger_front/parent"), std::string::npos) << e.what();
  }
}

TEST(Config, DefaultsAndOneLineErrorsNamingTheParameter) {
  XmlRpc::XmlRpcValue world, table;
  world["robot"]["motors"]["left"]["drive"] = std::string("left");
  world["robot"]["motors"]["right"]["drive"] = std::string("right");
  const WorldConfig c = parseWorldConfig(world, "/sim/world", table, "/table");
  EXPECT_DOUBLE_EQ(c.table.length, 3.0);
  EXPECT_EQ(c.table.beacons.size(), 3u);
  EXPECT_EQ(c.robot.motors.size(), 2u);

  XmlRpc::XmlRpcValue bad = world;
  bad["robot"]["wheel_radius"] = -0.03;
  try {
    parseWorldConfig(bad, "/sim/world", table, "/table");
    FAIL() << "negative wheel radius accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("/sim/world/robot/wheel_radius"), std::string::npos) << e.what();
  }
  bad = world;
  bad["robot"]["rangers"]["front"]["type"] = std::string("lidar");
  try {
    parseWorldConfig(bad, "/sim/world", table, "/table");
    FAIL() << "unknown ranger type accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("srf02, sharp"), std::string::npos) << e.what();
  }
  bad = world;
  bad["robot"]["encoders"]["x"]["motor"] = std::string("nope");
  EXPECT_THROW(parseWorldConfig(bad, "/sim/world", table, "/table"), ConfigError);
  XmlRpc::XmlRpcValue one_motor;
  one_motor["robot"]["motors"]["left"]["drive"] = std::string("left");
  EXPECT_THROW(parseWorldConfig(one_motor, "/sim/world", table, "/table"), ConfigError);
}
