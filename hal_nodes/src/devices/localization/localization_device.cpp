// Localization: Monte Carlo Localization (hal_nodes/mcl, on MRPT's particle filter) from the
// HAL devices' outputs. Inputs register with the filter and interpret their own data:
//   advancing  odometry: /odom, or several encoder pairs (/hal/odometry/<pair>) averaged by reliability
//   checking   beacons (/hal/beacons/ranges), compass (/hal/compass/heading), rangers
//              (/hal/rangers/<name>) against the table borders, bumpers (/hal/bumpers/contacts),
//              and the table model (from /table: off-table and in-obstacle poses are impossible)
// Every input message is an event processed in header-stamp order once the newest odometry is
// ~latency newer (input_events.h): a bag replayed through this device alone gives the same
// estimates run after run with a fixed ~seed.
//
// Outputs: /mcl/pose (geometry_msgs/PoseWithCovarianceStamped), /mcl/quality
// (hal_nodes/LocalizationQuality: probability the estimate is right, lost flag), /mcl/particlecloud
// (geometry_msgs/PoseArray), /mcl/beacon_belts (visualization_msgs/MarkerArray), tf map -> odom
// (REP-105, from the estimate and /odom's odom -> base_link at the same stamp). Outputs carry the
// stamp of the newest odometry applied: the time the particles' motion refers to.
// In: /initialpose (rviz "2D Pose Estimate"); service ~global_localization (std_srvs/Empty).
//
// Parameters (besides ~rate; all optional, defaults in brackets):
//   ~seed [1]  ~particles [2000]  ~min_particles [200]  ~adaptive [true] (KLD)
//   ~kld_epsilon [0.02] ~kld_z [2.33] ~kld_bin_xy [0.02 m] ~kld_bin_theta [0.05 rad]
//   ~resampling [systematic] (multinomial|residual|stratified|systematic)  ~ess_threshold [0.5]
//   ~alpha_slow [0.01] ~alpha_fast [0.2] ~lost_ratio [0.05] ~reset_fraction [1.0] ~recovery_time [2 s]
//   ~quality_tolerance [0.05 m] ("right" = within this of the truth) ~track_hazard [1e-4] (filter.h)
//   ~robot_radius [0.0 m]: the table margin   ~obstacles: list of [x0, y0, x1, y1] fixed obstacles
//   ~initial_pose [x, y, theta]: start there (else entirely lost: global localization)
//   ~initial_std_xy [0.02]  ~initial_std_theta [0.02]
//   ~odom_topic [/odom]  ~pairs/<name>/{topic, reliability}: encoder pairs (else /odom alone)
//   ~motion/{trans_per_trans, trans_per_rot, lateral_per_trans, rot_per_trans, rot_per_rot,
//            slip_probability, slip_trans, slip_rot, slip_accel [5 m/s^2, 0: no detection], slip_margin [0.001 m]}
//   ~beacons/{enabled [true], topic [/hal/beacons/ranges], reliability [1], range_std [0.015],
//             use_measurement_variance [true], range_std_auto [false], outlier_probability [0.05],
//             outlier_span [0.6], intersection_gain [4], intersection_below [0.5], belt_max_age [0.25],
//             max_speed [1.0]}
//   ~compass/{enabled [false], topic [/hal/compass/heading], reliability [0.5], std [0.05],
//             use_measurement_variance [true], outlier_probability [0.1], min_interval [0.1]}
//   ~rangers_reliability [0.5]  ~rangers/<name>/{topic [/hal/rangers/<name>], x, y, yaw,
//             min_range [0.03], max_range [2.0], std [0.02], short_probability [0.2], min_interval [0.05],
//             beam_width [-1: each reading's field_of_view; rad, full cone: the nearest echo in it]}
//   ~bumpers_topic [/hal/bumpers/contacts]  ~bumpers/<name>/{x, y}  ~bumpers_reliability [0.5]
//   ~map_frame [map] ~odom_frame [odom] ~base_frame [base_link] ~publish_tf [true]
//   ~transform_tolerance [0.1 s]  ~latency [0.05 s]  ~cloud_rate [5 Hz]
#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <hal_nodes/BeaconRange.h>
#include <hal_nodes/Contacts.h>
#include <hal_nodes/Heading.h>
#include <hal_nodes/LocalizationQuality.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/Range.h>
#include <std_srvs/Empty.h>
#include <tf2/LinearMath/Quaternion.h>
#include <tf2/utils.h>
#include <tf2_ros/transform_broadcaster.h>
#include <visualization_msgs/MarkerArray.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "hal_nodes/device_nodelet.h"
#include "hal_nodes/devices/config_blocks.h"
#include "hal_nodes/mcl/mcl.h"
#include "input_events.h"

namespace hal_nodes {

namespace {

using mcl::Pose2D;

struct Payload {
  enum Kind { kOdom, kPair, kBeacon, kCompass, kRanger, kBumpers } kind = kOdom;
  int index = 0;
  double a = 0, b = 0, c = 0;
  std::vector<std::string> closed;
};

Pose2D poseOf(const geometry_msgs::Pose& p) { return {p.position.x, p.position.y, tf2::getYaw(p.orientation)}; }

geometry_msgs::Pose toMsg(const Pose2D& p) {
  geometry_msgs::Pose m;
  m.position.x = p.x;
  m.position.y = p.y;
  tf2::Quaternion q;
  q.setRPY(0, 0, p.theta);
  m.orientation.x = q.x();
  m.orientation.y = q.y();
  m.orientation.z = q.z();
  m.orientation.w = q.w();
  return m;
}

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

class LocalizationDevice : public Device {
 public:
  LocalizationDevice() : events_(20000) {}

  void init(DeviceContext& ctx) override {
    ros::NodeHandle& pnh = ctx.pnh;
    nh_ = ctx.nh;
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
    table_ = std::make_shared<mcl::TableModel>(length, width, radius, obstacles);

    // ---- the filter ----
    mcl::FilterConfig fc;
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
    filter_ = std::make_unique<mcl::Filter>(fc, table_);

    // ---- advancing input: odometry ----
    mcl::MotionModel mm;
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
    const std::string odom_topic = optionalString(pnh, "odom_topic", "/odom");
    std::vector<mcl::OdometryInput::Pair> pairs;
    std::vector<std::string> pair_topics;
    for (const auto& name : optionalBlockNames(pnh, "pairs")) {
      const double rel = sub(pnh, "pairs/" + name, "reliability", 1.0);
      requireInRange(pnh, "pairs/" + name + "/reliability", rel, 1e-6, 1.0);
      pairs.push_back({name, rel});
      pair_topics.push_back(optionalString(pnh, "pairs/" + name + "/topic", "/hal/odometry/" + name));
    }
    use_pairs_ = !pairs.empty();
    if (!use_pairs_) pairs.push_back({"odom", 1.0});
    odom_ = std::make_shared<mcl::OdometryInput>(pairs, mm);
    filter_->addAdvancing(odom_);
    subs_.push_back(nh_.subscribe<nav_msgs::Odometry>(odom_topic, 200, [this](const nav_msgs::Odometry::ConstPtr& m) {
      Payload p;
      p.kind = Payload::kOdom;
      const Pose2D q = poseOf(m->pose.pose);
      p.a = q.x, p.b = q.y, p.c = q.theta;
      // The primary odometry goes after the pairs of the same stamp: it triggers the step.
      push(m->header.stamp, 1, std::move(p));
    }));
    for (std::size_t i = 0; i < pair_topics.size(); ++i) {
      subs_.push_back(nh_.subscribe<nav_msgs::Odometry>(pair_topics[i], 200, [this, i](const nav_msgs::Odometry::ConstPtr& m) {
        Payload p;
        p.kind = Payload::kPair;
        p.index = static_cast<int>(i);
        const Pose2D q = poseOf(m->pose.pose);
        p.a = q.x, p.b = q.y, p.c = q.theta;
        push(m->header.stamp, 0, std::move(p));
      }));
    }

    // ---- checking inputs ----
    if (optionalBool(pnh, "beacons/enabled", true)) {
      mcl::BeaconBeltsConfig bc;
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
      beacons_ = std::make_shared<mcl::BeaconBelts>(bc, table_);
      filter_->addChecking(beacons_);
      filter_->addSampler(beacons_);
      subs_.push_back(nh_.subscribe<BeaconRange>(optionalString(pnh, "beacons/topic", "/hal/beacons/ranges"), 200,
                                                 [this](const BeaconRange::ConstPtr& m) {
                                                   Payload p;
                                                   p.kind = Payload::kBeacon;
                                                   p.index = m->beacon_id;
                                                   p.a = m->range;
                                                   p.b = m->variance;
                                                   push(m->header.stamp, 2, std::move(p));
                                                 }));
    }
    if (optionalBool(pnh, "compass/enabled", false)) {
      mcl::CompassConfig cc;
      cc.reliability = sub(pnh, "compass", "reliability", cc.reliability);
      requireInRange(pnh, "compass/reliability", cc.reliability, 0.0, 1.0);
      cc.std = sub(pnh, "compass", "std", cc.std);
      requireInRange(pnh, "compass/std", cc.std, 1e-4, 3.2);
      cc.use_measurement_variance = optionalBool(pnh, "compass/use_measurement_variance", cc.use_measurement_variance);
      cc.outlier_probability = sub(pnh, "compass", "outlier_probability", cc.outlier_probability);
      requireInRange(pnh, "compass/outlier_probability", cc.outlier_probability, 0.0, 0.99);
      cc.min_interval = sub(pnh, "compass", "min_interval", cc.min_interval);
      requireInRange(pnh, "compass/min_interval", cc.min_interval, 0.0, 60.0);
      compass_ = std::make_shared<mcl::Compass>(cc);
      filter_->addChecking(compass_);
      subs_.push_back(nh_.subscribe<Heading>(optionalString(pnh, "compass/topic", "/hal/compass/heading"), 100,
                                             [this](const Heading::ConstPtr& m) {
                                               Payload p;
                                               p.kind = Payload::kCompass;
                                               p.a = m->yaw;
                                               p.b = m->variance;
                                               push(m->header.stamp, 2, std::move(p));
                                             }));
    }
    std::vector<mcl::RangerConfig> rangers;
    std::vector<std::string> ranger_topics;
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
      rangers.push_back(r);
      ranger_topics.push_back(optionalString(pnh, b + "/topic", "/hal/rangers/" + name));
    }
    if (!rangers.empty()) {
      const double rel = optionalDouble(pnh, "rangers_reliability", 0.5);
      requireInRange(pnh, "rangers_reliability", rel, 0.0, 1.0);
      rangers_ = std::make_shared<mcl::Rangers>(rangers, rel, table_);
      filter_->addChecking(rangers_);
      for (std::size_t i = 0; i < ranger_topics.size(); ++i)
        subs_.push_back(nh_.subscribe<sensor_msgs::Range>(ranger_topics[i], 100, [this, i](const sensor_msgs::Range::ConstPtr& m) {
          Payload p;
          p.kind = Payload::kRanger;
          p.index = static_cast<int>(i);
          p.a = m->range;
          p.b = m->field_of_view;
          push(m->header.stamp, 2, std::move(p));
        }));
    }
    std::vector<mcl::BumperConfig> bumpers;
    for (const auto& name : optionalBlockNames(pnh, "bumpers"))
      bumpers.push_back({name, sub(pnh, "bumpers/" + name, "x", 0.0), sub(pnh, "bumpers/" + name, "y", 0.0)});
    if (!bumpers.empty()) {
      mcl::BumpersOptions bo;
      bo.reliability = optionalDouble(pnh, "bumpers_reliability", bo.reliability);
      requireInRange(pnh, "bumpers_reliability", bo.reliability, 0.0, 1.0);
      bumpers_ = std::make_shared<mcl::Bumpers>(bumpers, bo, table_);
      filter_->addChecking(bumpers_);
      subs_.push_back(nh_.subscribe<Contacts>(optionalString(pnh, "bumpers_topic", "/hal/bumpers/contacts"), 100,
                                              [this](const Contacts::ConstPtr& m) {
                                                Payload p;
                                                p.kind = Payload::kBumpers;
                                                p.closed = m->closed;
                                                push(m->header.stamp, 2, std::move(p));
                                              }));
    }

    // ---- frames, timing, outputs ----
    map_frame_ = optionalString(pnh, "map_frame", "map");
    odom_frame_ = optionalString(pnh, "odom_frame", "odom");
    base_frame_ = optionalString(pnh, "base_frame", "base_link");
    publish_tf_ = optionalBool(pnh, "publish_tf", true);
    tf_tolerance_ = optionalDouble(pnh, "transform_tolerance", 0.1);
    requireInRange(pnh, "transform_tolerance", tf_tolerance_, 0.0, 10.0);
    latency_ = optionalDouble(pnh, "latency", 0.05);
    requireInRange(pnh, "latency", latency_, 0.0, 5.0);
    const double cloud_rate = optionalDouble(pnh, "cloud_rate", 5.0);
    requireInRange(pnh, "cloud_rate", cloud_rate, 0.01, 1000.0);
    cloud_period_ = 1.0 / cloud_rate;

    const std::vector<double> initial = optionalDoubleList(pnh, "initial_pose", {});
    if (!initial.empty() && initial.size() != 3)
      throw ParameterError("parameter " + qualified(pnh, "initial_pose") + " must be [x, y, theta]");
    const double std_xy = optionalDouble(pnh, "initial_std_xy", 0.02);
    requireInRange(pnh, "initial_std_xy", std_xy, 0.0, 10.0);
    const double std_th = optionalDouble(pnh, "initial_std_theta", 0.02);
    requireInRange(pnh, "initial_std_theta", std_th, 0.0, 10.0);
    if (initial.size() == 3) filter_->setPose({initial[0], initial[1], initial[2]}, std_xy, std_th);
    else filter_->globalLocalization();

    pose_pub_ = nh_.advertise<geometry_msgs::PoseWithCovarianceStamped>("/mcl/pose", 10);
    quality_pub_ = nh_.advertise<LocalizationQuality>("/mcl/quality", 10);
    cloud_pub_ = nh_.advertise<geometry_msgs::PoseArray>("/mcl/particlecloud", 1);
    belts_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("/mcl/beacon_belts", 1);
    initial_sub_ = nh_.subscribe<geometry_msgs::PoseWithCovarianceStamped>(
        "/initialpose", 2, [this](const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& m) { onInitialPose(*m); });
    global_srv_ = pnh.advertiseService<std_srvs::Empty::Request, std_srvs::Empty::Response>(
        "global_localization", [this](std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
          std::lock_guard<std::mutex> lk(filter_mutex_);
          filter_->globalLocalization();
          ROS_INFO("%s: global localization: particles spread over the free table", name_.c_str());
          return true;
        });
    name_ = ctx.name;
  }

  void refresh() override {
    const auto t0 = std::chrono::steady_clock::now();
    std::size_t steps = 0;
    {
      std::lock_guard<std::mutex> lk(filter_mutex_);
      // Everything up to `latency` before the newest odometry has arrived; without odometry
      // for a while, measurements are processed anyway after a longer wait.
      double watermark, newest_any;
      {
        std::lock_guard<std::mutex> lk2(stamp_mutex_);
        watermark = newest_odom_ - latency_;
        newest_any = newest_any_;
      }
      const double now = ros::Time::now().toSec();
      if (now - 1.0 > watermark && newest_any > 0.0) watermark = std::max(watermark, std::min(newest_any, now - 1.0));
      for (auto& e : events_.takeUntil(watermark)) {
        if (apply(e.stamp, e.payload)) {
          filter_->update(e.stamp);
          ++steps;
          last_step_ = e.stamp;
        }
      }
      updates_ += steps;
      // The particles stand where the newest applied odometry put them: the estimate is stamped
      // with that odometry's stamp, not a later measurement's (odometry stalled on a loaded HCL
      // would otherwise date an old position as new). Nothing new to date: nothing published.
      const double stamp = have_odom_ ? odom_stamp_ : last_step_;
      if (steps > 0 && stamp != published_stamp_) {  // != : a replayed bag may restart the clock
        published_stamp_ = stamp;
        publish(stamp);
      }
    }
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (steps > 0) {
      cost_ms_ = ms / static_cast<double>(steps);
      cost_max_ms_ = std::max(cost_max_ms_, cost_ms_);
    }
    if (!have_odom_) setUnavailable("no odometry received yet");
    else if (filter_->estimate().lost) setUnavailable("lost: recovering (global localization / sensor resetting)");
    else setAvailable();
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    std::lock_guard<std::mutex> lk(filter_mutex_);
    const auto& e = filter_->estimate();
    stat.add("probability", e.probability);
    stat.add("tracking probability (measurement evidence)", e.tracking);
    stat.add("lost", e.lost);
    stat.add("particles", e.particles);
    stat.add("effective sample size", e.ess);
    stat.add("filter steps", updates_);
    stat.add("resamplings", filter_->resamplings());
    stat.add("resets (sensor resetting)", filter_->resets());
    stat.add("wheel slips detected", odom_->slips());
    stat.add("cost per step [ms]", cost_ms_);
    stat.add("max cost per step [ms]", cost_max_ms_);
    stat.add("events dropped (queue full)", events_.dropped());
    stat.add("events too late (older than processed)", events_.late());
    stat.add("bad input values", bad_inputs_);
    if (beacons_) stat.add("beacon ranges rejected", beacons_->rejected());
  }

 private:
  void push(const ros::Time& stamp, int order, Payload p) {
    const double t = stamp.toSec();
    if (!std::isfinite(t) || t <= 0.0) {
      ++bad_inputs_;
      return;
    }
    {
      std::lock_guard<std::mutex> lk(stamp_mutex_);
      if (p.kind == Payload::kOdom) newest_odom_ = std::max(newest_odom_, t);
      newest_any_ = std::max(newest_any_, t);
    }
    events_.push(t, order, std::move(p));
  }

  // Hands one event to its input; true when it calls for a filter step.
  bool apply(double stamp, const Payload& p) {
    switch (p.kind) {
      case Payload::kOdom: {
        const Pose2D q{p.a, p.b, p.c};
        if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.theta)) {
          ++bad_inputs_;
          return false;
        }
        odom_pose_ = q;
        odom_stamp_ = stamp;
        have_odom_ = true;
        if (!use_pairs_) odom_->addPose(0, q, stamp);
        return true;
      }
      case Payload::kPair: {
        const Pose2D q{p.a, p.b, p.c};
        if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.theta)) {
          ++bad_inputs_;
          return false;
        }
        odom_->addPose(static_cast<std::size_t>(p.index), q, stamp);
        return false;  // the primary odometry of the same stamp makes the step
      }
      case Payload::kBeacon:
        return beacons_->addRange(stamp, p.index, p.a, p.b);
      case Payload::kCompass:
        return compass_->addHeading(stamp, p.a, p.b);
      case Payload::kRanger:
        return rangers_->addRange(static_cast<std::size_t>(p.index), stamp, p.a, p.b);
      case Payload::kBumpers:
        bumpers_->setClosed(stamp, p.closed);
        return true;
    }
    return false;
  }

  void onInitialPose(const geometry_msgs::PoseWithCovarianceStamped& m) {
    if (!m.header.frame_id.empty() && m.header.frame_id != map_frame_) {
      ROS_WARN("%s: /initialpose in frame '%s' ignored: expected '%s'", name_.c_str(), m.header.frame_id.c_str(), map_frame_.c_str());
      return;
    }
    const Pose2D p = poseOf(m.pose.pose);
    double sxy = std::sqrt(std::max(0.0, 0.5 * (m.pose.covariance[0] + m.pose.covariance[7])));
    double sth = std::sqrt(std::max(0.0, m.pose.covariance[35]));
    if (!(sxy > 0.0) || !std::isfinite(sxy)) sxy = 0.05;
    if (!(sth > 0.0) || !std::isfinite(sth)) sth = 0.1;
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.theta)) return;
    std::lock_guard<std::mutex> lk(filter_mutex_);
    filter_->setPose(p, sxy, sth);
    ROS_INFO("%s: initial pose (%.3f, %.3f, %.3f) +- %.3f m, %.3f rad", name_.c_str(), p.x, p.y, p.theta, sxy, sth);
  }

  void publish(double at) {
    const auto& e = filter_->estimate();
    const ros::Time stamp(at);
    geometry_msgs::PoseWithCovarianceStamped pose;
    pose.header.stamp = stamp;
    pose.header.frame_id = map_frame_;
    pose.pose.pose = toMsg(e.pose);
    const int idx[3] = {0, 1, 5};  // x, y, yaw in the 6x6 covariance
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) pose.pose.covariance[idx[r] * 6 + idx[c]] = e.cov[r * 3 + c];
    pose_pub_.publish(pose);

    LocalizationQuality q;
    q.header = pose.header;
    q.probability = e.probability;
    q.lost = e.lost;
    q.particles = static_cast<uint32_t>(e.particles);
    q.effective_sample_size = e.ess;
    quality_pub_.publish(q);

    if (publish_tf_ && have_odom_) {
      // map -> odom = estimate (map -> base) composed with the inverse of odom -> base at the same step.
      const Pose2D inv_odom = mcl::between(odom_pose_, {0, 0, 0});
      const Pose2D map_odom = mcl::compose(e.pose, inv_odom);
      geometry_msgs::TransformStamped t;
      t.header.stamp = stamp + ros::Duration(tf_tolerance_);  // valid until the next step (as amcl)
      t.header.frame_id = map_frame_;
      t.child_frame_id = odom_frame_;
      const geometry_msgs::Pose pm = toMsg(map_odom);
      t.transform.translation.x = pm.position.x;
      t.transform.translation.y = pm.position.y;
      t.transform.rotation = pm.orientation;
      tf_.sendTransform(t);
    }

    if (at - last_cloud_ >= cloud_period_) {
      last_cloud_ = at;
      if (cloud_pub_.getNumSubscribers() > 0) {
        const auto& s = filter_->particles();
        geometry_msgs::PoseArray cloud;
        cloud.header = pose.header;
        cloud.poses.reserve(s.size());
        for (std::size_t i = 0; i < s.size(); ++i) cloud.poses.push_back(toMsg({s.x[i], s.y[i], s.theta[i]}));
        cloud_pub_.publish(cloud);
      }
      if (beacons_ && belts_pub_.getNumSubscribers() > 0) publishBelts(stamp);
    }
  }

  // One circle per beacon whose latest range is recent: the belt the particles are weighed by.
  void publishBelts(const ros::Time& stamp) {
    visualization_msgs::MarkerArray arr;
    const auto& cfg = beacons_->config();
    const auto& latest = beacons_->latest();
    for (std::size_t id = 0; id < latest.size(); ++id) {
      visualization_msgs::Marker m;
      m.header.stamp = stamp;
      m.header.frame_id = map_frame_;
      m.ns = "beacon_belts";
      m.id = static_cast<int>(id);
      const bool fresh = last_step_ - latest[id].stamp <= std::max(0.5, cfg.belt_max_age);
      m.action = fresh ? visualization_msgs::Marker::ADD : visualization_msgs::Marker::DELETE;
      m.type = visualization_msgs::Marker::LINE_STRIP;
      m.pose.orientation.w = 1.0;
      m.scale.x = std::max(0.005, 2.0 * latest[id].sigma);  // the belt's width: +- sigma
      m.color.a = 0.6;
      m.color.r = id == 0 ? 1.0 : 0.2;
      m.color.g = id == 1 ? 1.0 : 0.2;
      m.color.b = id == 2 ? 1.0 : 0.2;
      if (fresh) {
        for (int k = 0; k <= 180; ++k) {
          geometry_msgs::Point p;
          const double a = 2.0 * M_PI * k / 180.0;
          p.x = cfg.beacons[id][0] + latest[id].range * std::cos(a);
          p.y = cfg.beacons[id][1] + latest[id].range * std::sin(a);
          m.points.push_back(p);
        }
      }
      arr.markers.push_back(m);
    }
    belts_pub_.publish(arr);
  }

  ros::NodeHandle nh_;
  std::string name_;
  std::shared_ptr<mcl::TableModel> table_;
  std::unique_ptr<mcl::Filter> filter_;
  std::shared_ptr<mcl::OdometryInput> odom_;
  std::shared_ptr<mcl::BeaconBelts> beacons_;
  std::shared_ptr<mcl::Compass> compass_;
  std::shared_ptr<mcl::Rangers> rangers_;
  std::shared_ptr<mcl::Bumpers> bumpers_;
  bool use_pairs_ = false;

  localization::InputEvents<Payload> events_;
  std::mutex stamp_mutex_;
  double newest_odom_ = -1e300, newest_any_ = 0.0;
  std::mutex filter_mutex_;
  Pose2D odom_pose_;
  bool have_odom_ = false;
  double last_step_ = 0.0, last_cloud_ = -1e300;
  double odom_stamp_ = 0.0, published_stamp_ = -1e300;  // the applied odometry's stamp; the last published
  unsigned long updates_ = 0, bad_inputs_ = 0;
  double cost_ms_ = 0.0, cost_max_ms_ = 0.0;

  std::string map_frame_, odom_frame_, base_frame_;
  bool publish_tf_ = true;
  double tf_tolerance_ = 0.1, latency_ = 0.05, cloud_period_ = 0.2;
  std::vector<ros::Subscriber> subs_;
  ros::Subscriber initial_sub_;
  ros::ServiceServer global_srv_;
  ros::Publisher pose_pub_, quality_pub_, cloud_pub_, belts_pub_;
  tf2_ros::TransformBroadcaster tf_;
};

}  // namespace hal_nodes

HAL_EXPORT_DEVICE(LocalizationDevice, Localization,
                  "Localization: Monte Carlo Localization on MRPT's particle filter (odometry, beacons, compass, rangers, bumpers, table model); /mcl/pose, /mcl/quality, map->odom tf.")
