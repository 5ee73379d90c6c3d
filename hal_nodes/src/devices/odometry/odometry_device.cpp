// Odometry: dead reckoning from one or more encoder pairs (driven wheels, undriven measuring
// wheels), each with a reliability weight. Publishes nav_msgs/Odometry on ~topic (/odom) and
// the odom -> base_link tf, plus each pair's own odometry on ~<pair> (/hal/odometry/<pair>),
// while someone subscribes, for whoever weighs the pairs itself.
//
// Each refresh samples the newest counter of every encoder (pull model). A pair takes part
// while both its counters are fresh; a stale pair drops out, and when it comes back its
// counters are re-baselined if the other pairs covered the gap (else the motion during the
// gap is still counted: nobody else saw it). With every pair stale the device publishes
// nothing (it never extrapolates) and reports STALE on /diagnostics.
//
// Parameters: read and described in configure() (the table: hal_nodes/PARAMETERS.md, make docs).
#include <geometry_msgs/TransformStamped.h>
#include <hcl_drivers/EncoderCounter.h>
#include <nav_msgs/Odometry.h>
#include <tf2_ros/transform_broadcaster.h>

#include <cmath>
#include <sstream>

#include "hal_nodes/device_nodelet.h"
#include <robot_core/params.h>
#include "hal_nodes/devices/odometry/encoder_tracker.h"
#include "hal_nodes/devices/odometry/pair_alignment.h"
#include "hal_nodes/devices/odometry/wheel_pair.h"

namespace hal_nodes {


namespace {

using Counter = hcl_drivers::EncoderCounter;

void fillPose(const PoseIntegrator& p, nav_msgs::Odometry& m) {
  m.pose.pose.position.x = p.pose().x;
  m.pose.pose.position.y = p.pose().y;
  m.pose.pose.orientation.z = std::sin(0.5 * p.pose().theta);
  m.pose.pose.orientation.w = std::cos(0.5 * p.pose().theta);
  // 6x6 row-major over (x, y, z, roll, pitch, yaw); z/roll/pitch are fixed by the plane.
  const int idx[3] = {0, 1, 5};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m.pose.covariance[idx[i] * 6 + idx[j]] = p.covariance()(i, j);
  for (int k : {2, 3, 4}) m.pose.covariance[k * 6 + k] = 1e6;  // unobserved by wheels
}

}  // namespace

class OdometryDevice : public Device {
 public:
  void configure(const robot_core::Params& params) override {
    params.describe("odom_frame", "the odometry's frame (the published pose's parent)");
    odom_frame_ = params.optionalString("odom_frame", "odom");
    params.describe("base_frame", "the robot's frame");
    base_frame_ = params.optionalString("base_frame", "base_link");
    params.describe("publish_tf", "broadcast the tf odom_frame -> base_frame");
    publish_tf_ = params.optionalBool("publish_tf", true);
    params.describe("max_input_age", "[s] a pair whose counters are older than this is stale and drops out");
    max_input_age_ = params.optionalDouble("max_input_age", 0.2);
    params.requirePositive("max_input_age", max_input_age_);
    const std::string plausible = params.renamed("plausible_wheel_speed", "max_wheel_speed");
    params.describe(plausible, "[m/s] a larger implied wheel speed is a bad sample: dropped, the pair re-baselined");
    plausible_wheel_speed_ = params.optionalDouble(plausible, 5.0);
    params.requirePositive(plausible, plausible_wheel_speed_);
    params.describe("topic", "the fused odometry out (nav_msgs/Odometry)");
    topic_ = params.optionalString("topic", "/odom");
    pairs_.clear();
    params.describe("pairs", "the encoder pairs, by name: each fused by reliability and also published on ~<name>");
    for (const auto& name : params.requireBlockNames("pairs")) {
      const robot_core::Params p = params.block("pairs/" + name);
      Pair pair;
      pair.name = name;
      p.describe("left_ticks_per_meter", "[1/m] left encoder ticks per metre, non-zero (negative: a mirrored encoder)");
      pair.model.left_m_per_tick = 1.0 / nonZero(p, "left_ticks_per_meter");
      p.describe("right_ticks_per_meter", "[1/m] right encoder ticks per metre, non-zero (negative: a mirrored encoder)");
      pair.model.right_m_per_tick = 1.0 / nonZero(p, "right_ticks_per_meter");
      // The driven wheels' pair has the robot's track; a pair of measuring wheels sets its own.
      p.describe("driven_wheels", "true: this pair counts the driven wheels, its track is the robot's (/robot/track_width)");
      const bool driven_wheels = p.optionalBool("driven_wheels", false);
      pair.model.track_width = robot_core::RobotGeometry::blockOrDescribed(
          p, "track_width", driven_wheels ? robot().track_width : std::nullopt, "track_width",
          "[m] the distance between this pair's wheels (required unless driven_wheels)");
      p.describe("reliability", "this pair's weight in the fusion");
      pair.reliability = p.optionalDouble("reliability", 1.0);
      p.requireInRange("reliability", pair.reliability, 1e-6, 1.0);
      p.describe("distance_noise", "[m/sqrt(m)] the distance's std after 1 m");
      pair.model.distance_noise = p.optionalDouble("distance_noise", 0.01);
      p.describe("heading_noise", "[rad/sqrt(m)] the heading's std after 1 m straight");
      pair.model.heading_noise = p.optionalDouble("heading_noise", 0.01);
      p.describe("rotation_noise", "[rad/sqrt(rad)] the heading's std after a 1 rad turn");
      pair.model.rotation_noise = p.optionalDouble("rotation_noise", 0.01);
      p.requireInRange("distance_noise", pair.model.distance_noise, 0.0, 1.0);
      p.requireInRange("heading_noise", pair.model.heading_noise, 0.0, 1.0);
      p.requireInRange("rotation_noise", pair.model.rotation_noise, 0.0, 1.0);
      p.describe("left", "the left encoder's counter topic in (hcl_drivers/EncoderCounter)");
      pair.left_topic = p.requireString("left");
      p.describe("right", "the right encoder's counter topic in (hcl_drivers/EncoderCounter)");
      pair.right_topic = p.requireString("right");
      pairs_.push_back(std::move(pair));
    }
  }

  void init(DeviceContext& ctx) override {
    using namespace hcl_drivers;  // the boards' messages
    for (Pair& pair : pairs_) {
      pair.left = addInput<Counter>(ctx.nh, pair.left_topic, pair.name + " left");
      pair.right = addInput<Counter>(ctx.nh, pair.right_topic, pair.name + " right");
      pair.pub = ctx.pnh.advertise<nav_msgs::Odometry>(pair.name, 5);
    }
    odom_pub_ = ctx.nh.advertise<nav_msgs::Odometry>(topic_, 5);
    if (publish_tf_) tf_ = std::make_unique<tf2_ros::TransformBroadcaster>();
  }

  void refresh() override {
    IncrementFusion fusion;
    ros::Time newest;
    double speed_sum = 0.0, turn_sum = 0.0, weight_sum = 0.0;
    for (auto& pair : pairs_) {
      const auto l = pair.left->fresh(max_input_age_);
      const auto r = pair.right->fresh(max_input_age_);
      if (!l || !r) {
        if (pair.active) {
          pair.active = false;
          pair.dropped_at_step = steps_;
          ++pair.dropouts;
          ROS_WARN("odometry: encoder pair %s stale, dropped out", pair.name.c_str());
        }
        continue;
      }
      if (!pair.active) {
        // Back (or first use): if other pairs integrated meanwhile, that motion is counted.
        if (pair.dropped_at_step < 0 || steps_ > pair.dropped_at_step) {
          pair.left_tracker.rebaseline();
          pair.right_tracker.rebaseline();
          pair.alignment.restart();
        }
        pair.active = true;
      }
      if (l->header.stamp > pair.left_used) {
        EncoderTracker::Event e;
        pair.left_ticks += pair.left_tracker.update(l->raw, l->bits, l->board_resets, &e);
        pair.left_used = l->header.stamp;
        countEvent(pair, e);
      }
      if (r->header.stamp > pair.right_used) {
        EncoderTracker::Event e;
        pair.right_ticks += pair.right_tracker.update(r->raw, r->bits, r->board_resets, &e);
        pair.right_used = r->header.stamp;
        countEvent(pair, e);
      }
      // The step ends at the newest instant both counters reached (pair_alignment.h).
      const auto step = pair.alignment.advance({pair.left_used.toSec(), static_cast<double>(pair.left_ticks)},
                                               {pair.right_used.toSec(), static_cast<double>(pair.right_ticks)});
      if (!step) {
        addPair(pair, OdometryIncrement(), fusion, newest, pair.last_stamp);  // no new common instant: no motion seen yet
        speed_sum += pair.reliability * pair.speed;
        turn_sum += pair.reliability * pair.turn_rate;
        weight_sum += pair.reliability;
        continue;
      }
      const ros::Time stamp = std::min(pair.left_used, pair.right_used);  // exactly the instant advance() chose
      OdometryIncrement inc = pair.model.increment(step->left_ticks, step->right_ticks);
      const double dt = step->dt;
      const double wheel_move = std::max(std::abs(pair.model.left_m_per_tick * step->left_ticks),
                                         std::abs(pair.model.right_m_per_tick * step->right_ticks));
      if (wheel_move > plausible_wheel_speed_ * dt + 1e-3) {
        // Implausible jump (garbled counter, undetected reboot): drop and re-baseline.
        ++pair.rejected;
        ROS_WARN_THROTTLE(1.0, "odometry: pair %s jumped %.3f m in %.3f s, sample dropped", pair.name.c_str(), wheel_move, dt);
        inc = OdometryIncrement();
      }
      pair.speed = inc.ds / dt;
      pair.turn_rate = inc.dtheta / dt;
      pair.last_stamp = stamp;
      addPair(pair, inc, fusion, newest, stamp);
      speed_sum += pair.reliability * pair.speed;
      turn_sum += pair.reliability * pair.turn_rate;
      weight_sum += pair.reliability;
    }

    if (fusion.empty()) {
      std::ostringstream why;
      why << "all encoder pairs stale:";
      for (const auto& p : pairs_)
        why << " " << p.name << " (left age " << p.left->age() << " s, right age " << p.right->age() << " s)";
      setUnavailable(why.str());
      all_stale_ = true;
      return;  // never extrapolate
    }
    setAvailable();
    all_stale_ = false;
    ++steps_;
    fused_.add(fusion.result());
    publish(odom_pub_, fused_, newest, speed_sum / weight_sum, turn_sum / weight_sum, true);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    if (all_stale_) stat.summary(diagnostic_msgs::DiagnosticStatus::STALE, stat.message);
    stat.addf("distance travelled [m]", "%.3f", fused_.distance());
    for (const auto& p : pairs_) {
      stat.add("pair " + p.name + " active", p.active);
      stat.add("pair " + p.name + " dropouts", p.dropouts);
      stat.add("pair " + p.name + " board resets seen", p.resets);
      stat.add("pair " + p.name + " rejected samples", p.rejected);
    }
  }

 private:
  struct Pair {
    std::string name;
    WheelPairModel model;
    double reliability = 1.0;
    std::string left_topic, right_topic;
    std::shared_ptr<LatestValue<Counter>> left, right;
    EncoderTracker left_tracker, right_tracker;
    int64_t left_ticks = 0, right_ticks = 0;  // unwrapped counts, summed from the trackers
    PairAlignment alignment;
    PoseIntegrator integrator;
    ros::Publisher pub;
    ros::Time last_stamp;
    ros::Time left_used, right_used;  // stamps of the counters last fed to the trackers
    bool active = false;
    long dropped_at_step = -1;  // fused step count when it dropped out; -1: never used yet
    double speed = 0.0, turn_rate = 0.0;
    unsigned long dropouts = 0, resets = 0, rejected = 0;
  };

  static double nonZero(const robot_core::Params& p, const std::string& name) {
    const double v = p.requireDouble(name);
    if (v == 0.0 || !std::isfinite(v))
      throw robot_core::ParameterError("parameter " + p.qualified(name) + " = 0: must be a non-zero number");
    return v;
  }

  void countEvent(Pair& pair, EncoderTracker::Event e) {
    if (e == EncoderTracker::Event::kBoardReset) {
      ++pair.resets;
      ROS_WARN("odometry: board of pair %s was reset, counter re-baselined", pair.name.c_str());
    } else if (e == EncoderTracker::Event::kBadWidth) {
      ++pair.rejected;
    }
  }

  void addPair(Pair& pair, const OdometryIncrement& inc, IncrementFusion& fusion, ros::Time& newest, const ros::Time& stamp) {
    fusion.add(inc, pair.reliability);
    if (stamp > newest) newest = stamp;
    pair.integrator.add(inc);
    // A pair's own odometry is for whoever weighs the pairs itself (a tool, a localization of
    // the team's): /odom is their fusion, the one the robot uses, so a pair is only published
    // to a subscriber. (Its integrator runs regardless: a subscriber sees the pair's whole path.)
    if (pair.pub.getNumSubscribers() > 0) publish(pair.pub, pair.integrator, stamp, pair.speed, pair.turn_rate, false);
  }

  void publish(ros::Publisher& pub, const PoseIntegrator& integ, const ros::Time& stamp, double v, double w, bool with_tf) {
    nav_msgs::Odometry m;
    m.header.stamp = stamp;
    m.header.frame_id = odom_frame_;
    m.child_frame_id = base_frame_;
    fillPose(integ, m);
    m.twist.twist.linear.x = v;
    m.twist.twist.angular.z = w;
    m.twist.covariance[0] = 1e-4 + 1e-2 * v * v;
    m.twist.covariance[7] = 1e-6;  // no lateral motion on a differential drive
    m.twist.covariance[35] = 1e-4 + 1e-2 * w * w;
    for (int k : {14, 21, 28}) m.twist.covariance[k] = 1e6;
    pub.publish(m);
    if (!with_tf || !tf_ || stamp == last_tf_stamp_) return;  // tf2 rejects repeated stamps
    last_tf_stamp_ = stamp;
    geometry_msgs::TransformStamped t;
    t.header = m.header;
    t.child_frame_id = base_frame_;
    t.transform.translation.x = m.pose.pose.position.x;
    t.transform.translation.y = m.pose.pose.position.y;
    t.transform.rotation = m.pose.pose.orientation;
    tf_->sendTransform(t);
  }

  std::vector<Pair> pairs_;
  PoseIntegrator fused_;
  ros::Publisher odom_pub_;
  std::unique_ptr<tf2_ros::TransformBroadcaster> tf_;
  ros::Time last_tf_stamp_;
  std::string odom_frame_, base_frame_, topic_;
  bool publish_tf_ = true;
  bool all_stale_ = false;
  double max_input_age_ = 0.2;
  double plausible_wheel_speed_ = 5.0;
  long steps_ = 0;
};

}  // namespace hal_nodes

HAL_EXPORT_DEVICE(OdometryDevice, Odometry,
                  "Odometry from one or more encoder pairs: /odom, odom->base_link tf, per-pair odometry.")
