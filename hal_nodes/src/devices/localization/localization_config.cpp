#include "localization_config.h"

#include <cmath>

#include <robot_core/params.h>

#include <algorithm>
#include <string>
#include <vector>

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

LocalizationConfig readLocalizationConfig(const Params& p, const Params& table) {
  LocalizationConfig c = readLocalizationConfig(p);
  readTableConfig(table, p, &c);
  return c;
}

void readTableConfig(const Params& table, const Params& p, LocalizationConfig* c) {
  // ---- the table (one source of truth: /table) ----
  c->table_length = table.requireDouble("length");
  c->table_width = table.requireDouble("width");
  table.requireInRange("length", c->table_length, 0.1, 100.0);
  table.requireInRange("width", c->table_width, 0.1, 100.0);
  // ~robot_radius (read with the device's block) is bounded by the table
  p.requireInRange("robot_radius", c->robot_radius, 0.0, 0.49 * std::min(c->table_length, c->table_width));
  if (c->beacons_enabled) {
    mcl::BeaconBeltsConfig& bc = c->beacons;
    bc.beacons.clear();
    for (const auto& b : table.optionalDoubleRows("beacons", 2)) bc.beacons.push_back({b[0], b[1]});
    if (bc.beacons.empty()) table.check("beacons", "must be a non-empty list of [x, y] beacon positions");
  }
}

LocalizationConfig readLocalizationConfig(const Params& p) {
  LocalizationConfig c;
  // ~robot_radius: its range depends on the table's size, checked by readTableConfig
  c.robot_radius = p.optionalDouble("robot_radius", c.robot_radius);
  for (const auto& o : p.optionalDoubleRows("obstacles", 4)) {
    if (!(o[0] < o[2] && o[1] < o[3])) p.check("obstacles", "each [x0, y0, x1, y1] needs x0 < x1 and y0 < y1");
    c.obstacles.push_back({o[0], o[1], o[2], o[3]});
  }

  // ---- the filter ----
  mcl::FilterConfig& fc = c.filter;
  const int seed = p.optionalInt("seed", 1);
  p.requireInRange("seed", seed, 0, 2147483647);
  fc.seed = static_cast<uint64_t>(seed);
  const int particles = p.optionalInt("particles", 2000);
  p.requireInRange("particles", particles, 10, 1000000);
  const int min_particles = p.optionalInt("min_particles", 200);
  p.requireInRange("min_particles", min_particles, 10, particles);
  fc.max_particles = static_cast<std::size_t>(particles);
  fc.min_particles = static_cast<std::size_t>(min_particles);
  fc.adaptive = p.optionalBool("adaptive", true);
  readInRange(p, "kld_epsilon", &fc.kld.epsilon, 1e-4, 1.0);
  readInRange(p, "kld_z", &fc.kld.z, 0.0, 10.0);
  fc.kld.bin_xy = p.optionalDouble("kld_bin_xy", fc.kld.bin_xy);
  p.requirePositive("kld_bin_xy", fc.kld.bin_xy);
  fc.kld.bin_theta = p.optionalDouble("kld_bin_theta", fc.kld.bin_theta);
  p.requirePositive("kld_bin_theta", fc.kld.bin_theta);
  const std::string resampling = p.optionalString("resampling", "systematic");
  p.requireOneOf("resampling", resampling, {"multinomial", "residual", "stratified", "systematic"});
  mcl::parseResampling(resampling, &fc.resampling);
  readInRange(p, "ess_threshold", &fc.ess_threshold, 0.0, 1.0);
  readInRange(p, "alpha_slow", &fc.alpha_slow, 1e-6, 0.5);
  readInRange(p, "alpha_fast", &fc.alpha_fast, fc.alpha_slow * 1.0001, 1.0);
  readInRange(p, "quality_tolerance", &fc.quality_tolerance, 1e-3, 1.0);
  readInRange(p, "track_hazard", &fc.track_hazard, 1e-6, 0.49);
  readInRange(p, "lost_ratio", &fc.lost_ratio, 0.0, 1.0);
  readInRange(p, "reset_fraction", &fc.reset_fraction, 0.01, 1.0);
  readInRange(p, "recovery_time", &fc.recovery_time, 0.0, 60.0);
  readInRange(p, "contradiction_nis", &fc.contradiction_nis, 0.0, 1e6);
  readInRange(p, "contradiction_window", &fc.contradiction_window, 0.01, 60.0);
  readInRange(p, "roughen_nis", &fc.roughen_nis, 0.0, 1e6);
  readInRange(p, "jitter_xy", &fc.jitter_xy, 0.0, 0.05);
  readInRange(p, "cluster_bin_xy", &fc.cluster_bin_xy, 1e-3, 10.0);
  readInRange(p, "cluster_bin_theta", &fc.cluster_bin_theta, 1e-3, M_PI);
  fc.contradiction_count = static_cast<std::size_t>(p.optionalDouble("contradiction_count", fc.contradiction_count));
  double input_count = static_cast<double>(fc.input_contradiction_count);
  readInRange(p, "input_contradiction_count", &input_count, 0.0, 1000.0);
  fc.input_contradiction_count = static_cast<std::size_t>(input_count);
  readInRange(p, "input_reset_fraction", &fc.input_reset_fraction, 0.0, 1.0);
  readInRange(p, "heading_known_std", &fc.heading_known_std, 0.0, M_PI);

  // ---- advancing input: odometry ----
  mcl::MotionModel& mm = c.motion;
  const std::pair<const char*, double*> motion[] = {
      {"trans_per_trans", &mm.trans_per_trans}, {"trans_per_rot", &mm.trans_per_rot},
      {"lateral_per_trans", &mm.lateral_per_trans}, {"rot_per_trans", &mm.rot_per_trans},
      {"rot_per_rot", &mm.rot_per_rot}, {"slip_probability", &mm.slip_probability},
      {"slip_trans", &mm.slip_trans}, {"slip_rot", &mm.slip_rot}, {"slip_accel", &mm.slip_accel},
      {"slip_margin", &mm.slip_margin}};
  for (const auto& m : motion) {
    const std::string name = m.first;
    readInRange(p, "motion/" + name, m.second, 0.0, name == "slip_probability" ? 1.0 : name == "slip_accel" ? 100.0 : 10.0);
  }
  c.odom_topic = p.optionalString("odom_topic", c.odom_topic);
  for (const auto& name : p.blockNames("pairs")) {
    double rel = 1.0;
    readInRange(p, "pairs/" + name + "/reliability", &rel, 1e-6, 1.0);
    c.pairs.push_back({name, rel});
    c.pair_topics.push_back(p.optionalString("pairs/" + name + "/topic", "/hal/odometry/" + name));
  }

  // ---- checking inputs ----
  c.beacons_enabled = p.optionalBool("beacons/enabled", c.beacons_enabled);
  if (c.beacons_enabled) {
    mcl::BeaconBeltsConfig& bc = c.beacons;  // the beacons' positions: /table (readTableConfig)
    readInRange(p, "beacons/reliability", &bc.reliability, 0.0, 1.0);
    readInRange(p, "beacons/range_std", &bc.range_std, 1e-4, 1.0);
    bc.use_measurement_variance = p.optionalBool("beacons/use_measurement_variance", bc.use_measurement_variance);
    bc.range_std_auto = p.optionalBool("beacons/range_std_auto", bc.range_std_auto);
    readInRange(p, "beacons/outlier_probability", &bc.outlier_probability, 0.0, 0.99);
    readInRange(p, "beacons/outlier_span", &bc.outlier_span, 0.01, 10.0);
    readInRange(p, "beacons/intersection_gain", &bc.intersection_gain, 0.0, 100.0);
    readInRange(p, "beacons/intersection_below", &bc.intersection_below, 0.0, 1.0);
    readInRange(p, "beacons/belt_max_age", &bc.belt_max_age, 0.0, 10.0);
    readInRange(p, "beacons/max_speed", &bc.max_speed, 0.0, 10.0);
    c.beacons_topic = p.optionalString("beacons/topic", c.beacons_topic);
  } else {
    p.unused("beacons");  // kept for when they are enabled again
  }
  c.compass_enabled = p.optionalBool("compass/enabled", c.compass_enabled);
  if (c.compass_enabled) {
    mcl::CompassConfig& cc = c.compass;
    readInRange(p, "compass/reliability", &cc.reliability, 0.0, 1.0);
    readInRange(p, "compass/std", &cc.std, 1e-4, 3.2);
    cc.use_measurement_variance = p.optionalBool("compass/use_measurement_variance", cc.use_measurement_variance);
    readInRange(p, "compass/outlier_probability", &cc.outlier_probability, 0.0, 0.99);
    readInRange(p, "compass/min_interval", &cc.min_interval, 0.0, 60.0);
    c.compass_topic = p.optionalString("compass/topic", c.compass_topic);
  } else {
    p.unused("compass");
  }
  for (const auto& name : p.blockNames("rangers")) {
    const std::string b = "rangers/" + name;
    mcl::RangerConfig r;
    r.name = name;
    r.x = p[b].optionalDouble("x", 0.0);
    r.y = p[b].optionalDouble("y", 0.0);
    r.yaw = p[b].optionalDouble("yaw", 0.0);
    r.min_range = p[b].optionalDouble("min_range", r.min_range);
    r.max_range = p[b].optionalDouble("max_range", r.max_range);
    p.requireInRange(b + "/min_range", r.min_range, 0.0, 10.0);
    p.requireInRange(b + "/max_range", r.max_range, r.min_range + 1e-3, 20.0);
    readInRange(p, b + "/std", &r.std, 1e-4, 2.0);
    readInRange(p, b + "/short_probability", &r.short_probability, 0.0, 0.99);
    readInRange(p, b + "/min_interval", &r.min_interval, 0.0, 60.0);
    r.beam_width = p[b].optionalDouble("beam_width", r.beam_width);
    if (r.beam_width >= 0.0) p.requireInRange(b + "/beam_width", r.beam_width, 0.0, M_PI);
    c.rangers.push_back(r);
    c.ranger_topics.push_back(p.optionalString(b + "/topic", "/hal/rangers/" + name));
  }
  readInRange(p, "rangers_reliability", &c.rangers_reliability, 0.0, 1.0);
  for (const auto& name : p.blockNames("bumpers"))
    c.bumpers.push_back({name, p["bumpers/" + name].optionalDouble("x", 0.0), p["bumpers/" + name].optionalDouble("y", 0.0)});
  readInRange(p, "bumpers_reliability", &c.bumpers_options.reliability, 0.0, 1.0);
  c.bumpers_topic = p.optionalString("bumpers_topic", c.bumpers_topic);

  // ---- frames, timing, outputs ----
  c.map_frame = p.optionalString("map_frame", c.map_frame);
  c.odom_frame = p.optionalString("odom_frame", c.odom_frame);
  c.base_frame = p.optionalString("base_frame", c.base_frame);
  c.publish_tf = p.optionalBool("publish_tf", c.publish_tf);
  readInRange(p, "transform_tolerance", &c.transform_tolerance, 0.0, 10.0);
  readInRange(p, "latency", &c.latency, 0.0, 5.0);
  const double cloud_rate = p.optionalDouble("cloud_rate", 5.0);
  p.requireInRange("cloud_rate", cloud_rate, 0.01, 1000.0);
  c.cloud_period = 1.0 / cloud_rate;

  c.initial_pose = p.optionalDoubleList("initial_pose");
  if (!c.initial_pose.empty() && c.initial_pose.size() != 3) p.check("initial_pose", "must be [x, y, theta]");
  readInRange(p, "initial_std_xy", &c.initial_std_xy, 0.0, 10.0);
  readInRange(p, "initial_std_theta", &c.initial_std_theta, 0.0, 10.0);
  // amcl's save_pose_rate: 0.5 Hz by default, 0 never.
  const double save_pose_rate = p.optionalDouble("save_pose_rate", 0.5);
  p.requireInRange("save_pose_rate", save_pose_rate, 0.0, 100.0);
  c.save_pose_period = save_pose_rate > 0.0 ? 1.0 / save_pose_rate : 0.0;
  readInRange(p, "lost_error_after", &c.lost_error_after, 0.0, 60.0);
  return c;
}

}  // namespace localization
}  // namespace hal_nodes
