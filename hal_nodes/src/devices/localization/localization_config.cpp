#include "localization_config.h"

#include <array>
#include <string>
#include <vector>

#include <robot_core/parameter_blocks.h>

namespace hal_nodes {
namespace localization {

using namespace robot_core::parameter_reader;

namespace {

// A sub-parameter of a block, e.g. ~beacons/reliability.
double sub(const ros::NodeHandle& pnh, const std::string& block, const std::string& name, double fallback) {
  return optionalDouble(pnh, block + "/" + name, fallback);
}

// /table/beacons: a list of [x, y].
std::vector<std::array<double, 2>> readBeacons(const ros::NodeHandle& nh, const std::string& name) {
  XmlRpc::XmlRpcValue v;
  if (!nh.getParam(name, v) || v.getType() != XmlRpc::XmlRpcValue::TypeArray || v.size() == 0)
    throw ParameterError("parameter " + qualified(nh, name) + " must be a non-empty list of [x, y] beacon positions");
  std::vector<std::array<double, 2>> out;
  for (int i = 0; i < v.size(); ++i) {
    auto& e = v[i];
    if (e.getType() != XmlRpc::XmlRpcValue::TypeArray || e.size() != 2)
      throw ParameterError("parameter " + qualified(nh, name) + "[" + std::to_string(i) + "] must be [x, y]");
    std::array<double, 2> b{};
    for (int k = 0; k < 2; ++k) {
      if (e[k].getType() == XmlRpc::XmlRpcValue::TypeDouble) b[k] = static_cast<double>(e[k]);
      else if (e[k].getType() == XmlRpc::XmlRpcValue::TypeInt) b[k] = static_cast<int>(e[k]);
      else throw ParameterError("parameter " + qualified(nh, name) + "[" + std::to_string(i) + "] must hold numbers");
    }
    out.push_back(b);
  }
  return out;
}

}  // namespace

LocalizationConfig readLocalizationConfig(const ros::NodeHandle& pnh) {
  LocalizationConfig c;
  // ---- the table (one source of truth: /table) ----
  ros::NodeHandle table_nh("/table");
  const double length = requireDouble(table_nh, "length");
  const double width = requireDouble(table_nh, "width");
  requireInRange(table_nh, "length", length, 0.1, 100.0);
  requireInRange(table_nh, "width", width, 0.1, 100.0);
  const double radius = optionalDouble(pnh, "robot_radius", 0.0);
  requireInRange(pnh, "robot_radius", radius, 0.0, 0.49 * std::min(length, width));
  std::vector<mcl::Rect> obstacles;
  XmlRpc::XmlRpcValue obs;
  if (pnh.getParam("obstacles", obs)) {
    const std::string err = "parameter " + qualified(pnh, "obstacles") + " must be a list of [x0, y0, x1, y1] with x0 < x1, y0 < y1";
    if (obs.getType() != XmlRpc::XmlRpcValue::TypeArray) throw ParameterError(err);
    for (int i = 0; i < obs.size(); ++i) {
      if (obs[i].getType() != XmlRpc::XmlRpcValue::TypeArray || obs[i].size() != 4) throw ParameterError(err);
      double v[4];
      for (int k = 0; k < 4; ++k) {
        if (obs[i][k].getType() == XmlRpc::XmlRpcValue::TypeDouble) v[k] = static_cast<double>(obs[i][k]);
        else if (obs[i][k].getType() == XmlRpc::XmlRpcValue::TypeInt) v[k] = static_cast<int>(obs[i][k]);
        else throw ParameterError(err);
      }
      if (!(v[0] < v[2] && v[1] < v[3])) throw ParameterError(err);
      obstacles.push_back({v[0], v[1], v[2], v[3]});
    }
  }
  c.table_length = length;
  c.table_width = width;
  c.robot_radius = radius;
  c.obstacles = obstacles;

  // ---- the filter ----
  mcl::FilterConfig& fc = c.filter;
  const int seed = optionalInt(pnh, "seed", 1);
  requireInRange(pnh, "seed", seed, 0, 2147483647);
  fc.seed = static_cast<uint64_t>(seed);
  const int particles = optionalInt(pnh, "particles", 2000);
  requireInRange(pnh, "particles", particles, 10, 1000000);
  const int min_particles = optionalInt(pnh, "min_particles", 200);
  requireInRange(pnh, "min_particles", min_particles, 10, particles);
  fc.max_particles = static_cast<std::size_t>(particles);
  fc.min_particles = static_cast<std::size_t>(min_particles);
  fc.adaptive = optionalBool(pnh, "adaptive", true);
  fc.kld.epsilon = optionalDouble(pnh, "kld_epsilon", fc.kld.epsilon);
  requireInRange(pnh, "kld_epsilon", fc.kld.epsilon, 1e-4, 1.0);
  fc.kld.z = optionalDouble(pnh, "kld_z", fc.kld.z);
  requireInRange(pnh, "kld_z", fc.kld.z, 0.0, 10.0);
  fc.kld.bin_xy = optionalDouble(pnh, "kld_bin_xy", fc.kld.bin_xy);
  requirePositive(pnh, "kld_bin_xy", fc.kld.bin_xy);
  fc.kld.bin_theta = optionalDouble(pnh, "kld_bin_theta", fc.kld.bin_theta);
  requirePositive(pnh, "kld_bin_theta", fc.kld.bin_theta);
  const std::string resampling = optionalString(pnh, "resampling", "systematic");
  requireOneOf(pnh, "resampling", resampling, {"multinomial", "residual", "stratified", "systematic"});
  mcl::parseResampling(resampling, &fc.resampling);
  fc.ess_threshold = optionalDouble(pnh, "ess_threshold", fc.ess_threshold);
  requireInRange(pnh, "ess_threshold", fc.ess_threshold, 0.0, 1.0);
  fc.alpha_slow = optionalDouble(pnh, "alpha_slow", fc.alpha_slow);
  requireInRange(pnh, "alpha_slow", fc.alpha_slow, 1e-6, 0.5);
  fc.alpha_fast = optionalDouble(pnh, "alpha_fast", fc.alpha_fast);
  requireInRange(pnh, "alpha_fast", fc.alpha_fast, fc.alpha_slow * 1.0001, 1.0);
  fc.quality_tolerance = optionalDouble(pnh, "quality_tolerance", fc.quality_tolerance);
  requireInRange(pnh, "quality_tolerance", fc.quality_tolerance, 1e-3, 1.0);
  fc.track_hazard = optionalDouble(pnh, "track_hazard", fc.track_hazard);
  requireInRange(pnh, "track_hazard", fc.track_hazard, 1e-6, 0.49);
  fc.lost_ratio = optionalDouble(pnh, "lost_ratio", fc.lost_ratio);
  requireInRange(pnh, "lost_ratio", fc.lost_ratio, 0.0, 1.0);
  fc.reset_fraction = optionalDouble(pnh, "reset_fraction", fc.reset_fraction);
  requireInRange(pnh, "reset_fraction", fc.reset_fraction, 0.01, 1.0);
  fc.recovery_time = optionalDouble(pnh, "recovery_time", fc.recovery_time);
  requireInRange(pnh, "recovery_time", fc.recovery_time, 0.0, 60.0);

  // ---- advancing input: odometry ----
  mcl::MotionModel& mm = c.motion;
  const std::pair<const char*, double*> motion[] = {
      {"trans_per_trans", &mm.trans_per_trans}, {"trans_per_rot", &mm.trans_per_rot},
      {"lateral_per_trans", &mm.lateral_per_trans}, {"rot_per_trans", &mm.rot_per_trans},
      {"rot_per_rot", &mm.rot_per_rot}, {"slip_probability", &mm.slip_probability},
      {"slip_trans", &mm.slip_trans}, {"slip_rot", &mm.slip_rot}, {"slip_accel", &mm.slip_accel},
      {"slip_margin", &mm.slip_margin}};
  for (const auto& m : motion) {
    *m.second = sub(pnh, "motion", m.first, *m.second);
    const std::string name = m.first;
    requireInRange(pnh, "motion/" + name, *m.second, 0.0,
                   name == "slip_probability" ? 1.0 : name == "slip_accel" ? 100.0 : 10.0);
  }
  c.odom_topic = optionalString(pnh, "odom_topic", c.odom_topic);
  for (const auto& name : optionalBlockNames(pnh, "pairs")) {
    const double rel = sub(pnh, "pairs/" + name, "reliability", 1.0);
    requireInRange(pnh, "pairs/" + name + "/reliability", rel, 1e-6, 1.0);
    c.pairs.push_back({name, rel});
    c.pair_topics.push_back(optionalString(pnh, "pairs/" + name + "/topic", "/hal/odometry/" + name));
  }

  // ---- checking inputs ----
  c.beacons_enabled = optionalBool(pnh, "beacons/enabled", c.beacons_enabled);
  if (c.beacons_enabled) {
    mcl::BeaconBeltsConfig& bc = c.beacons;
    bc.beacons = readBeacons(table_nh, "beacons");
    bc.reliability = sub(pnh, "beacons", "reliability", bc.reliability);
    requireInRange(pnh, "beacons/reliability", bc.reliability, 0.0, 1.0);
    bc.range_std = sub(pnh, "beacons", "range_std", bc.range_std);
    requireInRange(pnh, "beacons/range_std", bc.range_std, 1e-4, 1.0);
    bc.use_measurement_variance = optionalBool(pnh, "beacons/use_measurement_variance", bc.use_measurement_variance);
    bc.range_std_auto = optionalBool(pnh, "beacons/range_std_auto", bc.range_std_auto);
    bc.outlier_probability = sub(pnh, "beacons", "outlier_probability", bc.outlier_probability);
    requireInRange(pnh, "beacons/outlier_probability", bc.outlier_probability, 0.0, 0.99);
    bc.outlier_span = sub(pnh, "beacons", "outlier_span", bc.outlier_span);
    requireInRange(pnh, "beacons/outlier_span", bc.outlier_span, 0.01, 10.0);
    bc.intersection_gain = sub(pnh, "beacons", "intersection_gain", bc.intersection_gain);
    requireInRange(pnh, "beacons/intersection_gain", bc.intersection_gain, 0.0, 100.0);
    bc.intersection_below = sub(pnh, "beacons", "intersection_below", bc.intersection_below);
    requireInRange(pnh, "beacons/intersection_below", bc.intersection_below, 0.0, 1.0);
    bc.belt_max_age = sub(pnh, "beacons", "belt_max_age", bc.belt_max_age);
    requireInRange(pnh, "beacons/belt_max_age", bc.belt_max_age, 0.0, 10.0);
    bc.max_speed = sub(pnh, "beacons", "max_speed", bc.max_speed);
    requireInRange(pnh, "beacons/max_speed", bc.max_speed, 0.0, 10.0);
    c.beacons_topic = optionalString(pnh, "beacons/topic", c.beacons_topic);
  }
  c.compass_enabled = optionalBool(pnh, "compass/enabled", c.compass_enabled);
  if (c.compass_enabled) {
    mcl::CompassConfig& cc = c.compass;
    cc.reliability = sub(pnh, "compass", "reliability", cc.reliability);
    requireInRange(pnh, "compass/reliability", cc.reliability, 0.0, 1.0);
    cc.std = sub(pnh, "compass", "std", cc.std);
    requireInRange(pnh, "compass/std", cc.std, 1e-4, 3.2);
    cc.use_measurement_variance = optionalBool(pnh, "compass/use_measurement_variance", cc.use_measurement_variance);
    cc.outlier_probability = sub(pnh, "compass", "outlier_probability", cc.outlier_probability);
    requireInRange(pnh, "compass/outlier_probability", cc.outlier_probability, 0.0, 0.99);
    cc.min_interval = sub(pnh, "compass", "min_interval", cc.min_interval);
    requireInRange(pnh, "compass/min_interval", cc.min_interval, 0.0, 60.0);
    c.compass_topic = optionalString(pnh, "compass/topic", c.compass_topic);
  }
  for (const auto& name : optionalBlockNames(pnh, "rangers")) {
    const std::string b = "rangers/" + name;
    mcl::RangerConfig r;
    r.name = name;
    r.x = sub(pnh, b, "x", 0.0);
    r.y = sub(pnh, b, "y", 0.0);
    r.yaw = sub(pnh, b, "yaw", 0.0);
    r.min_range = sub(pnh, b, "min_range", r.min_range);
    r.max_range = sub(pnh, b, "max_range", r.max_range);
    requireInRange(pnh, b + "/min_range", r.min_range, 0.0, 10.0);
    requireInRange(pnh, b + "/max_range", r.max_range, r.min_range + 1e-3, 20.0);
    r.std = sub(pnh, b, "std", r.std);
    requireInRange(pnh, b + "/std", r.std, 1e-4, 2.0);
    r.short_probability = sub(pnh, b, "short_probability", r.short_probability);
    requireInRange(pnh, b + "/short_probability", r.short_probability, 0.0, 0.99);
    r.min_interval = sub(pnh, b, "min_interval", r.min_interval);
    requireInRange(pnh, b + "/min_interval", r.min_interval, 0.0, 60.0);
    r.beam_width = sub(pnh, b, "beam_width", r.beam_width);
    if (r.beam_width >= 0.0) requireInRange(pnh, b + "/beam_width", r.beam_width, 0.0, M_PI);
    c.rangers.push_back(r);
    c.ranger_topics.push_back(optionalString(pnh, b + "/topic", "/hal/rangers/" + name));
  }
  c.rangers_reliability = optionalDouble(pnh, "rangers_reliability", c.rangers_reliability);
  requireInRange(pnh, "rangers_reliability", c.rangers_reliability, 0.0, 1.0);
  for (const auto& name : optionalBlockNames(pnh, "bumpers"))
    c.bumpers.push_back({name, sub(pnh, "bumpers/" + name, "x", 0.0), sub(pnh, "bumpers/" + name, "y", 0.0)});
  c.bumpers_options.reliability = optionalDouble(pnh, "bumpers_reliability", c.bumpers_options.reliability);
  requireInRange(pnh, "bumpers_reliability", c.bumpers_options.reliability, 0.0, 1.0);
  c.bumpers_topic = optionalString(pnh, "bumpers_topic", c.bumpers_topic);

  // ---- frames, timing, outputs ----
  c.map_frame = optionalString(pnh, "map_frame", c.map_frame);
  c.odom_frame = optionalString(pnh, "odom_frame", c.odom_frame);
  c.base_frame = optionalString(pnh, "base_frame", c.base_frame);
  c.publish_tf = optionalBool(pnh, "publish_tf", c.publish_tf);
  c.transform_tolerance = optionalDouble(pnh, "transform_tolerance", c.transform_tolerance);
  requireInRange(pnh, "transform_tolerance", c.transform_tolerance, 0.0, 10.0);
  c.latency = optionalDouble(pnh, "latency", c.latency);
  requireInRange(pnh, "latency", c.latency, 0.0, 5.0);
  const double cloud_rate = optionalDouble(pnh, "cloud_rate", 5.0);
  requireInRange(pnh, "cloud_rate", cloud_rate, 0.01, 1000.0);
  c.cloud_period = 1.0 / cloud_rate;

  c.initial_pose = optionalDoubleList(pnh, "initial_pose", {});
  if (!c.initial_pose.empty() && c.initial_pose.size() != 3)
    throw ParameterError("parameter " + qualified(pnh, "initial_pose") + " must be [x, y, theta]");
  c.initial_std_xy = optionalDouble(pnh, "initial_std_xy", c.initial_std_xy);
  requireInRange(pnh, "initial_std_xy", c.initial_std_xy, 0.0, 10.0);
  c.initial_std_theta = optionalDouble(pnh, "initial_std_theta", c.initial_std_theta);
  requireInRange(pnh, "initial_std_theta", c.initial_std_theta, 0.0, 10.0);
  return c;
}

}  // namespace localization
}  // namespace hal_nodes
