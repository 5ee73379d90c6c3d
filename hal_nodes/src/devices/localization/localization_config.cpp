#include "localization_config.h"

#include <cmath>

#include <robot_core/params.h>

#include <algorithm>
#include <string>
#include <vector>

#include "hal_nodes/described_number.h"

namespace hal_nodes {
namespace localization {

namespace {

using robot_core::Params;

// An optional number kept at its default unless set, then checked to lie in [lo, hi].
void readInRange(const Params& p, const std::string& name, double* value, double lo, double hi) {
  *value = p.optionalDouble(name, *value);
  p.requireInRange(name, *value, lo, hi);
}

}  // namespace

LocalizationConfig readLocalizationConfig(const Params& p, const Params& table, const robot_core::RobotGeometry& robot) {
  LocalizationConfig c = readLocalizationConfig(p, robot);
  readTableConfig(table, p, &c);
  return c;
}

void readTableConfig(const Params& table, const Params& p, LocalizationConfig* c) {
  // ---- the table (one source of truth: /table) ----
  table.describe("length", "[m] the table's x extent (the map frame's origin at a corner)");
  c->table_length = table.requireDouble("length");
  table.describe("width", "[m] the table's y extent");
  c->table_width = table.requireDouble("width");
  table.requireInRange("length", c->table_length, 0.1, 100.0);
  table.requireInRange("width", c->table_width, 0.1, 100.0);
  // ~robot_radius (read with the device's block) is bounded by the table
  p.requireInRange("robot_radius", c->robot_radius, 0.0, 0.49 * std::min(c->table_length, c->table_width));
  if (c->beacons_enabled) {
    mcl::BeaconBeltsConfig& bc = c->beacons;
    bc.beacons.clear();
    table.describe("beacons", "[m] the beacons' positions [x, y] in the map frame, by id (with the beacons enabled)");
    for (const auto& b : table.optionalDoubleRows("beacons", 2)) bc.beacons.push_back({b[0], b[1]});
    if (bc.beacons.empty()) table.check("beacons", "must be a non-empty list of [x, y] beacon positions");
  }
}

LocalizationConfig readLocalizationConfig(const Params& p, const robot_core::RobotGeometry& robot) {
  LocalizationConfig c;
  // ~robot_radius: its range depends on the table's size, checked by readTableConfig
  c.robot_radius = robot_core::RobotGeometry::blockOrDescribed(
      p, "robot_radius", robot.radius, "radius",
      "[m] the table margin: the robot's centre keeps this far from the borders and obstacles", c.robot_radius);
  p.describe("obstacles", "[m] fixed obstacles on the table, a list of [x0, y0, x1, y1]");
  for (const auto& o : p.optionalDoubleRows("obstacles", 4)) {
    if (!(o[0] < o[2] && o[1] < o[3])) p.check("obstacles", "each [x0, y0, x1, y1] needs x0 < x1 and y0 < y1");
    c.obstacles.push_back({o[0], o[1], o[2], o[3]});
  }

  // ---- the filter ----
  mcl::FilterConfig& fc = c.filter;
  p.describe("seed", "the filter's random seed: a replayed bag gives the same estimates with the same seed");
  const int seed = p.optionalInt("seed", 1);
  p.requireInRange("seed", seed, 0, 2147483647);
  fc.seed = static_cast<uint64_t>(seed);
  p.describe("particles", "the most particles (the count when not adaptive)");
  const int particles = p.optionalInt("particles", 2000);
  p.requireInRange("particles", particles, 10, 1000000);
  p.describe("min_particles", "the fewest particles KLD sampling keeps (adaptive)");
  const int min_particles = p.optionalInt("min_particles", 200);
  p.requireInRange("min_particles", min_particles, 10, particles);
  fc.max_particles = static_cast<std::size_t>(particles);
  fc.min_particles = static_cast<std::size_t>(min_particles);
  p.describe("adaptive", "KLD sampling: the count between min_particles and particles follows the cloud's spread");
  fc.adaptive = p.optionalBool("adaptive", true);
  p.describe("kld_epsilon", "KLD sampling: the bound of the KL divergence between the particles and the posterior");
  readInRange(p, "kld_epsilon", &fc.kld.epsilon, 1e-4, 1.0);
  p.describe("kld_z", "KLD sampling: the upper standard normal quantile of 1 - delta (2.33: delta = 0.01)");
  readInRange(p, "kld_z", &fc.kld.z, 0.0, 10.0);
  p.describe("kld_bin_xy", "[m] KLD sampling: the histogram's bin in x and y");
  fc.kld.bin_xy = p.optionalDouble("kld_bin_xy", fc.kld.bin_xy);
  p.requirePositive("kld_bin_xy", fc.kld.bin_xy);
  p.describe("kld_bin_theta", "[rad] KLD sampling: the histogram's bin in heading");
  fc.kld.bin_theta = p.optionalDouble("kld_bin_theta", fc.kld.bin_theta);
  p.requirePositive("kld_bin_theta", fc.kld.bin_theta);
  p.describe("resampling", "the resampling scheme");
  const std::string resampling = p.optionalString("resampling", "systematic");
  p.requireOneOf("resampling", resampling, {"multinomial", "residual", "stratified", "systematic"});
  mcl::parseResampling(resampling, &fc.resampling);
  p.describe("ess_threshold", "resample when the effective sample size per particle falls below this");
  readInRange(p, "ess_threshold", &fc.ess_threshold, 0.0, 1.0);
  p.describe("alpha_slow", "rate of the slow likelihood average (per monitored measurement)");
  readInRange(p, "alpha_slow", &fc.alpha_slow, 1e-6, 0.5);
  p.describe("alpha_fast", "rate of the fast likelihood average (per monitored measurement), above alpha_slow");
  readInRange(p, "alpha_fast", &fc.alpha_fast, fc.alpha_slow * 1.0001, 1.0);
  p.describe("quality_tolerance", "[m] the estimate is \"right\" within this of the truth (the quality's probability)");
  readInRange(p, "quality_tolerance", &fc.quality_tolerance, 1e-3, 1.0);
  p.describe("track_hazard", "chance of a switch between tracking and not, per measurement with evidence (kidnap, slip)");
  readInRange(p, "track_hazard", &fc.track_hazard, 1e-6, 0.49);
  p.describe("lost_ratio", "lost when the fast likelihood average over the slow one falls below this");
  readInRange(p, "lost_ratio", &fc.lost_ratio, 0.0, 1.0);
  p.describe("reset_fraction", "share of the set replaced by sensor proposals when lost");
  readInRange(p, "reset_fraction", &fc.reset_fraction, 0.01, 1.0);
  p.describe("recovery_time", "[s] after a reset, every resampling roughens the set this long (heading diversity)");
  readInRange(p, "recovery_time", &fc.recovery_time, 0.0, 60.0);
  p.describe("contradiction_nis", "lost (kidnap) when the window's median normalized innovation exceeds it (0: off)");
  readInRange(p, "contradiction_nis", &fc.contradiction_nis, 0.0, 1e6);
  p.describe("contradiction_window", "[s] the window of measurements the kidnap test judges");
  readInRange(p, "contradiction_window", &fc.contradiction_window, 0.01, 60.0);
  p.describe("roughen_nis", "the set is roughened (a slip to catch up with) when the window's median is above this");
  readInRange(p, "roughen_nis", &fc.roughen_nis, 0.0, 1e6);
  p.describe("jitter_xy", "[m] position jitter at every resampling, so a still robot's cloud can follow the beacons");
  readInRange(p, "jitter_xy", &fc.jitter_xy, 0.0, 0.05);
  p.describe("cluster_bin_xy", "[m] the cell in x and y of the grid the cloud is clustered on when it spreads wider");
  readInRange(p, "cluster_bin_xy", &fc.cluster_bin_xy, 1e-3, 10.0);
  p.describe("cluster_bin_theta", "[rad] the cell in heading of the grid the cloud is clustered on");
  readInRange(p, "cluster_bin_theta", &fc.cluster_bin_theta, 1e-3, M_PI);
  p.describe("contradiction_count", "measurements the window needs before the kidnap test judges");
  fc.contradiction_count = static_cast<std::size_t>(p.optionalDouble("contradiction_count", fc.contradiction_count));
  double input_count = static_cast<double>(fc.input_contradiction_count);
  p.describe("input_contradiction_count", "one input's measurements in the window before it alone can contradict the set");
  readInRange(p, "input_contradiction_count", &input_count, 0.0, 1000.0);
  fc.input_contradiction_count = static_cast<std::size_t>(input_count);
  p.describe("input_reset_fraction", "share of the set an input contradicting the rest redraws with what it measures");
  readInRange(p, "input_reset_fraction", &fc.input_reset_fraction, 0.0, 1.0);
  p.describe("heading_known_std", "[rad] after a reset from ranges, the heading counts as known below this spread (0: off)");
  readInRange(p, "heading_known_std", &fc.heading_known_std, 0.0, M_PI);

  // ---- advancing input: odometry ----
  mcl::MotionModel& mm = c.motion;
  // The motion model's noise (mcl/motion/motion_model.h): name, where it goes, what it means.
  const DescribedNumber motion[] = {
      {"trans_per_trans", &mm.trans_per_trans, "[m/m] forward noise (std) per metre travelled"},
      {"trans_per_rot", &mm.trans_per_rot, "[m/rad] forward noise (std) per radian turned"},
      {"lateral_per_trans", &mm.lateral_per_trans, "[m/m] sideways noise (std) per metre travelled"},
      {"rot_per_trans", &mm.rot_per_trans, "[rad/m] heading noise (std) per metre travelled"},
      {"rot_per_rot", &mm.rot_per_rot, "[rad/rad] heading noise (std) per radian turned"},
      {"slip_probability", &mm.slip_probability, "per increment, the chance of a slip the slip detection does not see"},
      {"slip_trans", &mm.slip_trans, "[m] a slip's loss of forward travel (std)"},
      {"slip_rot", &mm.slip_rot, "[rad] a slip's heading noise (std)"},
      {"slip_accel", &mm.slip_accel, "[m/s^2] travel beyond the last speed plus this is a slip (0: no detection)"},
      {"slip_margin", &mm.slip_margin, "[m] the travel beyond that a slip needs (encoder resolution and noise)"}};
  for (const auto& m : motion) {
    const std::string name = m.name;
    p.describe("motion/" + name, m.meaning);
    readInRange(p, "motion/" + name, m.value, 0.0, name == "slip_probability" ? 1.0 : name == "slip_accel" ? 100.0 : 10.0);
  }
  p.describe("odom_topic", "the odometry in (nav_msgs/Odometry), used when no pairs are set");
  c.odom_topic = p.optionalString("odom_topic", c.odom_topic);
  p.describe("pairs", "encoder pairs (the Odometry device's) averaged by reliability, by name; none: odom_topic");
  for (const auto& name : p.blockNames("pairs")) {
    double rel = 1.0;
    p.describe("pairs/" + name + "/reliability", "this pair's weight in the average of the increments");
    readInRange(p, "pairs/" + name + "/reliability", &rel, 1e-6, 1.0);
    c.pairs.push_back({name, rel});
    p.describe("pairs/" + name + "/topic", "this pair's odometry in (nav_msgs/Odometry)");
    c.pair_topics.push_back(p.optionalString("pairs/" + name + "/topic", "/hal/odometry/" + name));
  }

  // ---- checking inputs ----
  p.describe("beacons/enabled", "check the estimate with the beacon ranges (the beacons' positions: /table)");
  c.beacons_enabled = p.optionalBool("beacons/enabled", c.beacons_enabled);
  if (c.beacons_enabled) {
    mcl::BeaconBeltsConfig& bc = c.beacons;  // the beacons' positions: /table (readTableConfig)
    p.describe("beacons/reliability", "exponent of the beacons' likelihood: 0 ignored, 1 trusted");
    readInRange(p, "beacons/reliability", &bc.reliability, 0.0, 1.0);
    p.describe("beacons/range_std", "[m] a range's std when it carries no variance");
    readInRange(p, "beacons/range_std", &bc.range_std, 1e-4, 1.0);
    p.describe("beacons/use_measurement_variance", "use each range's own variance when it carries one");
    bc.use_measurement_variance = p.optionalBool("beacons/use_measurement_variance", bc.use_measurement_variance);
    p.describe("beacons/range_std_auto", "learn the ranges' std from the innovations");
    bc.range_std_auto = p.optionalBool("beacons/range_std_auto", bc.range_std_auto);
    p.describe("beacons/outlier_probability", "chance of a range being a reflection (a longer path)");
    readInRange(p, "beacons/outlier_probability", &bc.outlier_probability, 0.0, 0.99);
    p.describe("beacons/outlier_span", "[m] reflections are at most this much longer than the true range");
    readInRange(p, "beacons/outlier_span", &bc.outlier_span, 0.01, 10.0);
    p.describe("beacons/intersection_gain", "extra weight of particles where the belts of other beacons' recent ranges cross");
    readInRange(p, "beacons/intersection_gain", &bc.intersection_gain, 0.0, 100.0);
    p.describe("beacons/intersection_below", "the intersections weigh more while the quality is below this");
    readInRange(p, "beacons/intersection_below", &bc.intersection_below, 0.0, 1.0);
    p.describe("beacons/belt_max_age", "[s] a range older than this no longer forms a belt");
    readInRange(p, "beacons/belt_max_age", &bc.belt_max_age, 0.0, 10.0);
    p.describe("beacons/max_speed", "[m/s] an old belt is widened by max_speed times its age");
    readInRange(p, "beacons/max_speed", &bc.max_speed, 0.0, 10.0);
    p.describe("beacons/topic", "the beacon ranges in (hal_nodes/BeaconRange)");
    c.beacons_topic = p.optionalString("beacons/topic", c.beacons_topic);
  } else {
    p.unused("beacons");  // kept for when they are enabled again
  }
  p.describe("compass/enabled", "check the estimate with the compass's heading");
  c.compass_enabled = p.optionalBool("compass/enabled", c.compass_enabled);
  if (c.compass_enabled) {
    mcl::CompassConfig& cc = c.compass;
    p.describe("compass/reliability", "exponent of the compass's likelihood: 0 ignored, 1 trusted");
    readInRange(p, "compass/reliability", &cc.reliability, 0.0, 1.0);
    p.describe("compass/std", "[rad] a heading's std when it carries no variance");
    readInRange(p, "compass/std", &cc.std, 1e-4, 3.2);
    p.describe("compass/use_measurement_variance", "use each heading's own variance when it carries one");
    cc.use_measurement_variance = p.optionalBool("compass/use_measurement_variance", cc.use_measurement_variance);
    p.describe("compass/outlier_probability", "chance of a disturbed heading (the motors nearby)");
    readInRange(p, "compass/outlier_probability", &cc.outlier_probability, 0.0, 0.99);
    p.describe("compass/min_interval", "[s] between applied headings (successive readings are not independent)");
    readInRange(p, "compass/min_interval", &cc.min_interval, 0.0, 60.0);
    p.describe("compass/topic", "the headings in (hal_nodes/Heading)");
    c.compass_topic = p.optionalString("compass/topic", c.compass_topic);
  } else {
    p.unused("compass");
  }
  p.describe("rangers", "range finders measured against the table's borders and obstacles, by name");
  for (const auto& name : p.blockNames("rangers")) {
    const std::string b = "rangers/" + name;
    mcl::RangerConfig r;
    r.name = name;
    p[b].describe("x", "[m] the ranger's mounting position in base_link, x");
    r.x = p[b].optionalDouble("x", 0.0);
    p[b].describe("y", "[m] the ranger's mounting position in base_link, y");
    r.y = p[b].optionalDouble("y", 0.0);
    p[b].describe("yaw", "[rad] the ranger's direction in base_link");
    r.yaw = p[b].optionalDouble("yaw", 0.0);
    p[b].describe("min_range", "[m] the part's minimum: it reads this for anything nearer");
    r.min_range = p[b].optionalDouble("min_range", r.min_range);
    p[b].describe("max_range", "[m] the part's maximum: beyond, it reads nothing");
    r.max_range = p[b].optionalDouble("max_range", r.max_range);
    p.requireInRange(b + "/min_range", r.min_range, 0.0, 10.0);
    p.requireInRange(b + "/max_range", r.max_range, r.min_range + 1e-3, 20.0);
    p.describe(b + "/std", "[m] the range's noise (std)");
    readInRange(p, b + "/std", &r.std, 1e-4, 2.0);
    p.describe(b + "/short_probability", "chance of a reading short of the map (the opponent, a game element)");
    readInRange(p, b + "/short_probability", &r.short_probability, 0.0, 0.99);
    p.describe(b + "/min_interval", "[s] between applied readings of this ranger");
    readInRange(p, b + "/min_interval", &r.min_interval, 0.0, 60.0);
    p[b].describe("beam_width", "[rad] the full cone, the nearest echo in it (< 0: each reading's field_of_view)");
    r.beam_width = p[b].optionalDouble("beam_width", r.beam_width);
    if (r.beam_width >= 0.0) p.requireInRange(b + "/beam_width", r.beam_width, 0.0, M_PI);
    c.rangers.push_back(r);
    p.describe(b + "/topic", "this ranger's readings in (sensor_msgs/Range)");
    c.ranger_topics.push_back(p.optionalString(b + "/topic", "/hal/rangers/" + name));
  }
  p.describe("rangers_reliability", "exponent of the rangers' likelihood: 0 ignored, 1 trusted");
  readInRange(p, "rangers_reliability", &c.rangers_reliability, 0.0, 1.0);
  p.describe("bumpers", "the bumpers' contact points, by the names the contacts carry");
  for (const auto& name : p.blockNames("bumpers")) {
    p["bumpers/" + name].describe("x", "[m] the contact point in base_link, x");
    p["bumpers/" + name].describe("y", "[m] the contact point in base_link, y");
    c.bumpers.push_back({name, p["bumpers/" + name].optionalDouble("x", 0.0), p["bumpers/" + name].optionalDouble("y", 0.0)});
  }
  p.describe("bumpers_reliability", "exponent of the bumpers' likelihood: 0 ignored, 1 trusted");
  readInRange(p, "bumpers_reliability", &c.bumpers_options.reliability, 0.0, 1.0);
  p.describe("bumpers_topic", "the bumpers' contacts in (hal_nodes/Contacts)");
  c.bumpers_topic = p.optionalString("bumpers_topic", c.bumpers_topic);

  // ---- frames, timing, outputs ----
  p.describe("map_frame", "the map frame (the table's)");
  c.map_frame = p.optionalString("map_frame", c.map_frame);
  p.describe("odom_frame", "the odometry's frame");
  c.odom_frame = p.optionalString("odom_frame", c.odom_frame);
  p.describe("base_frame", "the robot's frame");
  c.base_frame = p.optionalString("base_frame", c.base_frame);
  p.describe("publish_tf", "publish the tf map -> odom");
  c.publish_tf = p.optionalBool("publish_tf", c.publish_tf);
  p.describe("transform_tolerance", "[s] the map -> odom transform is valid this long (as amcl's)");
  readInRange(p, "transform_tolerance", &c.transform_tolerance, 0.0, 10.0);
  p.describe("latency", "[s] inputs wait this long behind the newest odometry, to be processed in stamp order");
  readInRange(p, "latency", &c.latency, 0.0, 5.0);
  p.describe("cloud_rate", "[Hz] how often the particle cloud is published");
  const double cloud_rate = p.optionalDouble("cloud_rate", 5.0);
  p.requireInRange("cloud_rate", cloud_rate, 0.01, 1000.0);
  c.cloud_period = 1.0 / cloud_rate;

  p.describe("initial_pose", "[m, m, rad] the start, [x, y, theta] (absent: entirely lost, global localization)");
  c.initial_pose = p.optionalDoubleList("initial_pose");
  if (!c.initial_pose.empty() && c.initial_pose.size() != 3) p.check("initial_pose", "must be [x, y, theta]");
  p.describe("initial_std_xy", "[m] the start position's spread (std)");
  readInRange(p, "initial_std_xy", &c.initial_std_xy, 0.0, 10.0);
  p.describe("initial_std_theta", "[rad] the start heading's spread (std)");
  readInRange(p, "initial_std_theta", &c.initial_std_theta, 0.0, 10.0);
  // amcl's save_pose_rate: 0.5 Hz by default, 0 never.
  p.describe("save_pose_rate", "[Hz] the estimate, while not lost, is written to initial_pose, initial_std_* (0: never)");
  const double save_pose_rate = p.optionalDouble("save_pose_rate", 0.5);
  p.requireInRange("save_pose_rate", save_pose_rate, 0.0, 100.0);
  c.save_pose_period = save_pose_rate > 0.0 ? 1.0 / save_pose_rate : 0.0;
  p.describe("lost_error_after", "[s] lost this long: unavailable (ERROR); shorter, a WARN while it re-localizes");
  readInRange(p, "lost_error_after", &c.lost_error_after, 0.0, 60.0);
  return c;
}

}  // namespace localization
}  // namespace hal_nodes
