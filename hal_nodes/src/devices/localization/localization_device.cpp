// Localization: Monte Carlo Localization (hal_nodes/mcl, on MRPT's particle filter) from the
// HAL devices' outputs. Inputs register with the filter and interpret their own data:
//   advancing  odometry: /odom, or several encoder pairs (/hal/odometry/<pair>) averaged by reliability
//   checking   beacons (/hal/beacons/ranges), compass (/hal/compass/heading), rangers
//              (/hal/rangers/<name>) against the table borders, bumpers (/hal/bumpers/contacts),
//              and the table model (from /table: off-table and in-obstacle poses are impossible)
// Every input message is an event processed in header-stamp order once the newest odometry is
// ~latency newer (input_events.h): a bag replayed through this device alone gives the same
// estimates run after run with a fixed ~seed. Each new /odom wakes the refresh at once, and the
// estimate goes out carried forward to that odometry (carried_pose.h): fresh, and still the same
// at the same stamp in a replay.
//
// Outputs: /mcl/pose (geometry_msgs/PoseWithCovarianceStamped: the heaviest particle cluster's
// mean and covariance, mcl/clusters.h), /mcl/quality
// (hal_nodes/LocalizationQuality: probability the estimate is right, lost flag), /mcl/particlecloud
// (geometry_msgs/PoseArray), /mcl/beacon_belts (visualization_msgs/MarkerArray), tf map -> odom
// (REP-105, from the estimate and /odom's odom -> base_link at the same stamp). The pose, quality
// and tf carry the stamp of the newest odometry received; the particle cloud and the belts that of
// the newest odometry applied: the time the particles' motion refers to.
// amcl's interface beside ours: /amcl_pose (latched), /particlecloud, the services
// /global_localization and /request_nomotion_update (std_srvs/Empty).
// In: /initialpose (rviz "2D Pose Estimate"); service ~global_localization (std_srvs/Empty).
//
// Parameters: read and described in readLocalizationConfig() (localization_config.cpp; the table:
// hal_nodes/PARAMETERS.md, make docs); the filter's settings are explained in mcl/filter.h.
// A filter lost for less than ~lost_error_after (a sensor reset after a slip against a wall,
// re-localized from the beacons within the second) is a WARN, not an ERROR: the quality says lost
// all along, so the driver holds meanwhile. While not lost, the estimate is written back to
// ~initial_pose, ~initial_std_xy and ~initial_std_theta (amcl's save_pose_rate), so a respawned
// HAL resumes where the robot was.
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <hal_nodes/BeaconRange.h>
#include <hal_nodes/Contacts.h>
#include <hal_nodes/Heading.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/Range.h>
#include <std_srvs/Empty.h>
#include <robot_core/geometry.h>

#include <chrono>
#include <cstdio>
#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <string>
#include <vector>
#include <optional>

#include "hal_nodes/device_nodelet.h"
#include "hal_nodes/mcl/mcl.h"
#include "carried_pose.h"
#include "input_events.h"
#include "localization_config.h"
#include "localization_outputs.h"

namespace hal_nodes {

namespace {

using mcl::Pose2D;
using localization::LocalizationConfig;
using localization::LocalizationOutputs;
using localization::NewestOdometry;
using localization::carryForward;

struct Payload {
  enum Kind { kOdom, kPair, kBeacon, kCompass, kRanger, kBumpers } kind = kOdom;
  int index = 0;
  double a = 0, b = 0, c = 0;
  std::vector<std::string> closed;
};

Pose2D poseOf(const geometry_msgs::Pose& p) { return {p.position.x, p.position.y, robot_core::yawOf(p.orientation)}; }

}  // namespace

class LocalizationDevice : public Device {
 public:
  LocalizationDevice() : events_(20000) {}

  void configure(const robot_core::Params& params) override {
    config_ = localization::readLocalizationConfig(params, robot());
    params_ = params;
  }

  void init(DeviceContext& ctx) override {
    nh_.emplace(ctx.nh);
    pnh_.emplace(ctx.pnh);
    name_ = ctx.name;
    // The table's size and beacons are the table's, outside the device's block: /table.
    LocalizationConfig c = config_;
    localization::readTableConfig(robot_core::Params::of(ros::NodeHandle("/table")), params_, &c);
    save_pose_period_ = c.save_pose_period;
    lost_error_after_ = c.lost_error_after;
    latency_ = c.latency;
    map_frame_ = c.map_frame;
    table_ = std::make_shared<mcl::TableModel>(c.table_length, c.table_width, c.robot_radius, c.obstacles);
    filter_ = std::make_unique<mcl::Filter>(c.filter, table_);
    addOdometry(c);
    addCheckingInputs(c);
    if (c.initial_pose.size() == 3) {
      filter_->setPose({c.initial_pose[0], c.initial_pose[1], c.initial_pose[2]}, c.initial_std_xy, c.initial_std_theta);
      ROS_INFO("%s: starting at (%.3f, %.3f, %.3f) +- %.3f m, %.3f rad (~initial_pose)", name_.c_str(), c.initial_pose[0],
               c.initial_pose[1], c.initial_pose[2], c.initial_std_xy, c.initial_std_theta);
    }
    else
      filter_->globalLocalization();

    outputs_ = std::make_unique<LocalizationOutputs>(*nh_, c);
    initial_sub_ = nh_->subscribe<geometry_msgs::PoseWithCovarianceStamped>(
        "/initialpose", 2, [this](const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& m) { onInitialPose(*m); });
    // Ours under the device's name, and amcl's names beside it.
    auto global = [this](std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
      std::lock_guard<std::mutex> lk(filter_mutex_);
      filter_->globalLocalization();
      // The spread cloud and "lost" out at once: the next measurement may already narrow it
      // (the beacons can give the position back in one step), and whoever asked (rviz, the
      // driver, a test) is to see that the particles were spread.
      const ros::Time now = ros::Time::now();
      outputs_->publishCloud(now, filter_->particles());
      outputs_->publishQuality(now, *filter_);
      ROS_INFO("%s: global localization: particles spread over the free table", name_.c_str());
      return true;
    };
    global_srv_ = ctx.pnh.advertiseService<std_srvs::Empty::Request, std_srvs::Empty::Response>("global_localization", global);
    amcl_global_srv_ = nh_->advertiseService<std_srvs::Empty::Request, std_srvs::Empty::Response>("/global_localization", global);
    // amcl's request_nomotion_update: an update without motion, and the particles published.
    // The filter applies every measurement even standing still (amcl waits for motion), so this
    // is one step now with what the inputs hold, and the cloud out at once.
    nomotion_srv_ = nh_->advertiseService<std_srvs::Empty::Request, std_srvs::Empty::Response>(
        "/request_nomotion_update", [this](std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
          std::lock_guard<std::mutex> lk(filter_mutex_);
          if (last_step_ > 0.0) filter_->update(last_step_);
          force_cloud_ = true;
          published_stamp_ = -1e300;  // the next refresh publishes, even with no new odometry
          return true;
        });
  }

  void refresh() override {
    const auto t0 = std::chrono::steady_clock::now();
    std::size_t steps = 0;
    {
      std::lock_guard<std::mutex> lk(filter_mutex_);
      // Everything up to `latency` before the newest odometry has arrived; without odometry
      // for a while, measurements are processed anyway after a longer wait.
      // One snapshot: the odometry the estimate is carried to is the one the watermark counts
      // from, so what is published at a stamp depends on nothing that arrived after it.
      double watermark, newest_any;
      NewestOdometry newest;
      std::vector<std::pair<double, Pose2D>> arrivals;  // odometry not published at yet
      {
        std::lock_guard<std::mutex> lk2(stamp_mutex_);
        watermark = newest_odom_ - latency_;
        newest_any = newest_any_;
        newest = newest_odom_pose_;
        arrivals.swap(unpublished_odom_);
      }
      // A refresh that comes late (a busy computer, a replay faster than the match) publishes
      // at every odometry stamp it missed, each from the inputs up to that stamp as a timely
      // one would have: the same estimates at the same stamps, however late it runs.
      std::sort(arrivals.begin(), arrivals.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      if (arrivals.size() > kMaxCatchUp) arrivals.erase(arrivals.begin(), arrivals.end() - kMaxCatchUp);
      for (const auto& [stamp, pose] : arrivals) {
        if (stamp >= newest.stamp() || stamp <= published_stamp_) continue;  // the newest: below, as always
        steps += stepUntil(stamp - latency_);
        if (have_odom_ && stamp >= odom_stamp_) publishAt(stamp, carryForward(filter_->estimate().pose, odom_pose_, pose));
      }
      const double now = ros::Time::now().toSec();
      if (now - 1.0 > watermark && newest_any > 0.0) watermark = std::max(watermark, std::min(newest_any, now - 1.0));
      steps += stepUntil(watermark);
      updates_ += steps;
      // The particles stand where the newest applied odometry put them; the odometry received
      // since carries the estimate to the present. Outputs are dated by odometry, never by a
      // later measurement (odometry stalled on a loaded HCL would otherwise date an old
      // position as new). Nothing new to date: nothing published.
      if (have_odom_) {
        const bool carry = newest.have() && newest.stamp() >= odom_stamp_;
        const double stamp = carry ? newest.stamp() : odom_stamp_;
        const Pose2D pose = carry ? carryForward(filter_->estimate().pose, odom_pose_, newest.pose())
                                  : filter_->estimate().pose;
        if (stamp != published_stamp_) publishAt(stamp, pose);
      } else if (steps > 0 && last_step_ != published_stamp_) {  // measurements without odometry
        published_stamp_ = last_step_;
        outputs_->publish(last_step_, filter_->estimate().pose, *filter_, last_step_, nullptr, beacons_.get(), last_step_,
                          force_cloud_);
        force_cloud_ = false;
      }
    }
    savePoseIfDue();
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (steps > 0) {
      cost_ms_ = ms / static_cast<double>(steps);
      cost_max_ms_ = std::max(cost_max_ms_, cost_ms_);
    }
    reportLost(filter_->estimate().lost);
  }

  // Lost: unavailable once it has lasted lost_error_after (sim time), a WARN until then.
  void reportLost(bool lost) {
    const double now = ros::Time::now().toSec();
    if (!lost) lost_since_ = -1.0;
    else if (lost_since_ < 0.0) lost_since_ = now;
    if (!have_odom_) {
      setUnavailable("no odometry received yet");
    } else if (lost && now - lost_since_ >= lost_error_after_) {
      setUnavailable("lost: recovering (global localization / sensor resetting)");
    } else if (lost) {
      setAvailable();
      char message[128];
      std::snprintf(message, sizeof(message), "lost %.1f s: re-localizing from its sensors (unavailable after %.1f s)",
                    now - lost_since_, lost_error_after_);
      setCondition(diagnostic_msgs::DiagnosticStatus::WARN, message);
    } else {
      setAvailable();
      clearCondition();
    }
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    std::lock_guard<std::mutex> lk(filter_mutex_);
    const auto& e = filter_->estimate();
    stat.add("probability", e.probability);
    stat.add("tracking probability (measurement evidence)", e.tracking);
    stat.add("lost", e.lost);
    stat.add("particles", e.particles);
    stat.add("effective sample size", e.ess);
    stat.add("clusters", e.clusters);
    stat.add("estimate's cluster share of the weight", e.cluster_weight);
    stat.add("filter steps", updates_);
    stat.add("resamplings", filter_->resamplings());
    stat.add("resets (sensor resetting)", filter_->resets());
    stat.add("input redraws (one input against the rest)", filter_->inputRedraws());
    stat.add("heading", filter_->headingUnknown() ? "unknown (not yet resolved by motion)" : "known");
    stat.add("wheel slips detected", odom_->slips());
    stat.add("cost per step [ms]", cost_ms_);
    stat.add("max cost per step [ms]", cost_max_ms_);
    stat.add("events dropped (queue full)", events_.dropped());
    stat.add("events too late (older than processed)", events_.late());
    stat.add("bad input values", bad_inputs_);
    if (beacons_) stat.add("beacon ranges rejected", beacons_->rejected());
  }

 private:
  // amcl's save_pose_rate: the estimate as the start of a respawned HAL. Not while lost: a
  // restart then begins lost as well, from the last pose that was sound.
  void savePoseIfDue() {
    if (save_pose_period_ <= 0.0) return;
    const double now = ros::Time::now().toSec();
    if (now - last_saved_ < save_pose_period_ && now >= last_saved_) return;
    Pose2D pose;
    double var_xy, var_theta;
    {
      std::lock_guard<std::mutex> lk(filter_mutex_);
      const auto& e = filter_->estimate();
      if (!have_odom_ || e.lost) return;
      pose = e.pose;
      var_xy = std::max(e.cov[0], e.cov[4]);
      var_theta = e.cov[8];
    }
    last_saved_ = now;
    // Never narrower than 10 cm / 0.15 rad: between the last save and a respawned HAL the robot
    // drives on until its wheels stop (the HCL's command timeout, the boards' watchdogs): up to
    // ~20 cm at match speed. A cloud that misses the truth converges confidently next to it.
    pnh_->setParam("initial_pose", std::vector<double>{pose.x, pose.y, pose.theta});
    pnh_->setParam("initial_std_xy", std::max(0.10, std::sqrt(std::max(0.0, var_xy))));
    pnh_->setParam("initial_std_theta", std::max(0.15, std::sqrt(std::max(0.0, var_theta))));
  }

  // The advancing input: /odom (primary, it triggers a step), or encoder pairs under it.
  void addOdometry(const LocalizationConfig& c) {
    use_pairs_ = !c.pairs.empty();
    std::vector<mcl::OdometryInput::Pair> pairs = c.pairs;
    if (!use_pairs_) pairs.push_back({"odom", 1.0});
    odom_ = std::make_shared<mcl::OdometryInput>(pairs, c.motion);
    filter_->addAdvancing(odom_);
    subs_.push_back(nh_->subscribe<nav_msgs::Odometry>(c.odom_topic, 200, [this](const nav_msgs::Odometry::ConstPtr& m) {
      // The primary odometry goes after the pairs of the same stamp: it triggers the step.
      push(m->header.stamp, 1, odometryPayload(Payload::kOdom, 0, *m));
      wakeRefresh(m->header.stamp);  // the estimate follows it out at once
    }, ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay()));
    for (std::size_t i = 0; i < c.pair_topics.size(); ++i)
      subs_.push_back(nh_->subscribe<nav_msgs::Odometry>(c.pair_topics[i], 200, [this, i](const nav_msgs::Odometry::ConstPtr& m) {
        push(m->header.stamp, 0, odometryPayload(Payload::kPair, static_cast<int>(i), *m));
      }));
  }

  static Payload odometryPayload(Payload::Kind kind, int index, const nav_msgs::Odometry& m) {
    Payload p;
    p.kind = kind;
    p.index = index;
    const Pose2D q = poseOf(m.pose.pose);
    p.a = q.x, p.b = q.y, p.c = q.theta;
    return p;
  }

  // Beacons, compass, rangers and bumpers: each weighs the particles when its block is configured.
  void addCheckingInputs(const LocalizationConfig& c) {
    if (c.beacons_enabled) {
      beacons_ = std::make_shared<mcl::BeaconBelts>(c.beacons, table_);
      filter_->addChecking(beacons_);
      filter_->addSampler(beacons_);
      subs_.push_back(nh_->subscribe<BeaconRange>(c.beacons_topic, 200, [this](const BeaconRange::ConstPtr& m) {
        push(m->header.stamp, 2, payload(Payload::kBeacon, m->beacon_id, m->range, m->variance));
      }));
    }
    if (c.compass_enabled) {
      compass_ = std::make_shared<mcl::Compass>(c.compass);
      filter_->addChecking(compass_);
      subs_.push_back(nh_->subscribe<Heading>(c.compass_topic, 100, [this](const Heading::ConstPtr& m) {
        push(m->header.stamp, 2, payload(Payload::kCompass, 0, m->yaw, m->variance));
      }));
    }
    if (!c.rangers.empty()) {
      rangers_ = std::make_shared<mcl::Rangers>(c.rangers, c.rangers_reliability, table_);
      filter_->addChecking(rangers_);
      for (std::size_t i = 0; i < c.ranger_topics.size(); ++i)
        subs_.push_back(nh_->subscribe<sensor_msgs::Range>(c.ranger_topics[i], 100, [this, i](const sensor_msgs::Range::ConstPtr& m) {
          push(m->header.stamp, 2, payload(Payload::kRanger, static_cast<int>(i), m->range, m->field_of_view));
        }));
    }
    if (!c.bumpers.empty()) {
      bumpers_ = std::make_shared<mcl::Bumpers>(c.bumpers, c.bumpers_options, table_);
      filter_->addChecking(bumpers_);
      subs_.push_back(nh_->subscribe<Contacts>(c.bumpers_topic, 100, [this](const Contacts::ConstPtr& m) {
        Payload p = payload(Payload::kBumpers, 0, 0.0, 0.0);
        p.closed = m->closed;
        push(m->header.stamp, 2, std::move(p));
      }));
    }
  }

  static Payload payload(Payload::Kind kind, int index, double a, double b) {
    Payload p;
    p.kind = kind;
    p.index = index;
    p.a = a;
    p.b = b;
    return p;
  }

  // The filter steps through the inputs up to `watermark` (filter_mutex_ held); how many steps.
  std::size_t stepUntil(double watermark) {
    std::size_t steps = 0;
    for (auto& e : events_.takeUntil(watermark)) {
      if (apply(e.stamp, e.payload)) {
        filter_->update(e.stamp);
        ++steps;
        last_step_ = e.stamp;
      }
    }
    return steps;
  }

  // The estimate out at an odometry stamp (filter_mutex_ held).
  void publishAt(double stamp, const Pose2D& pose) {
    published_stamp_ = stamp;
    outputs_->publish(stamp, pose, *filter_, odom_stamp_, &odom_pose_, beacons_.get(), last_step_, force_cloud_);
    force_cloud_ = false;
  }

  void push(const ros::Time& stamp, int order, Payload p) {
    const double t = stamp.toSec();
    if (!std::isfinite(t) || t <= 0.0) {
      ++bad_inputs_;
      return;
    }
    {
      std::lock_guard<std::mutex> lk(stamp_mutex_);
      if (p.kind == Payload::kOdom) {
        newest_odom_ = std::max(newest_odom_, t);
        const Pose2D q{p.a, p.b, p.c};
        if (std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.theta)) {
          newest_odom_pose_.offer(t, q);
          if (unpublished_odom_.size() < 4 * kMaxCatchUp) unpublished_odom_.emplace_back(t, q);
        }
      }
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

  std::optional<ros::NodeHandle> nh_;  // from init(): constructing a handle needs ros::init (a checker has none)
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
  localization::NewestOdometry newest_odom_pose_;  // what the published estimate is carried to
  std::vector<std::pair<double, Pose2D>> unpublished_odom_;  // odometry since the last refresh (stamp_mutex_)
  static constexpr std::size_t kMaxCatchUp = 100;  // a late refresh publishes at most this many missed stamps
  std::mutex filter_mutex_;
  Pose2D odom_pose_;
  bool have_odom_ = false;
  double last_step_ = 0.0;
  double odom_stamp_ = 0.0, published_stamp_ = -1e300;  // the applied odometry's stamp; the last published
  unsigned long updates_ = 0, bad_inputs_ = 0;
  double cost_ms_ = 0.0, cost_max_ms_ = 0.0;

  std::string map_frame_;
  double latency_ = 0.05;
  std::vector<ros::Subscriber> subs_;
  ros::Subscriber initial_sub_;
  ros::ServiceServer global_srv_, amcl_global_srv_, nomotion_srv_;
  bool force_cloud_ = false;  // request_nomotion_update: the cloud with the next publication
  std::optional<ros::NodeHandle> pnh_;  // from init(): constructing a handle needs ros::init (a checker has none)
  LocalizationConfig config_;  // the device's block, as configure() read it
  robot_core::Params params_;  // that block, to name ~robot_radius when the table refuses it
  double save_pose_period_ = 0.0;
  double lost_error_after_ = 1.0;
  double lost_since_ = -1.0;  // [s, sim time] when the filter last became lost; -1: not lost
  double last_saved_ = -1e9;
  std::unique_ptr<LocalizationOutputs> outputs_;
};

}  // namespace hal_nodes

HAL_EXPORT_DEVICE(LocalizationDevice, Localization,
                  "Localization: Monte Carlo Localization on MRPT's particle filter (odometry, beacons, compass, rangers, bumpers, table model); /mcl/pose, /mcl/quality, map->odom tf.")
