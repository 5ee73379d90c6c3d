#include "localization_outputs.h"

#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <hal_nodes/LocalizationQuality.h>
#include <tf2/LinearMath/Quaternion.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <cmath>

namespace hal_nodes {
namespace localization {

using mcl::Pose2D;

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

LocalizationOutputs::LocalizationOutputs(ros::NodeHandle& nh, const LocalizationConfig& config)
    : map_frame_(config.map_frame),
      odom_frame_(config.odom_frame),
      publish_tf_(config.publish_tf),
      tf_tolerance_(config.transform_tolerance),
      cloud_period_(config.cloud_period) {
  pose_pub_ = nh.advertise<geometry_msgs::PoseWithCovarianceStamped>("/mcl/pose", 10);
  quality_pub_ = nh.advertise<LocalizationQuality>("/mcl/quality", 10);
  cloud_pub_ = nh.advertise<geometry_msgs::PoseArray>("/mcl/particlecloud", 1);
  belts_pub_ = nh.advertise<visualization_msgs::MarkerArray>("/mcl/beacon_belts", 1);
  amcl_pose_pub_ = nh.advertise<geometry_msgs::PoseWithCovarianceStamped>("/amcl_pose", 2, true);
  amcl_cloud_pub_ = nh.advertise<geometry_msgs::PoseArray>("/particlecloud", 1);
}

void LocalizationOutputs::publishQuality(const ros::Time& stamp, const mcl::Filter& filter) {
  const auto& e = filter.estimate();
  LocalizationQuality q;
  q.header.stamp = stamp;
  q.header.frame_id = map_frame_;
  q.probability = e.probability;
  q.lost = e.lost;
  q.particles = static_cast<uint32_t>(e.particles);
  q.effective_sample_size = e.ess;
  quality_pub_.publish(q);
}

void LocalizationOutputs::publish(double at, const mcl::Pose2D& carried, const mcl::Filter& filter,
                                  double filter_stamp, const mcl::Pose2D* odom_pose, const mcl::BeaconBelts* beacons,
                                  double last_step, bool force_cloud) {
  const auto& e = filter.estimate();
  const ros::Time stamp(at);
  geometry_msgs::PoseWithCovarianceStamped pose;
  pose.header.stamp = stamp;
  pose.header.frame_id = map_frame_;
  pose.pose.pose = toMsg(carried);
  const int idx[3] = {0, 1, 5};  // x, y, yaw in the 6x6 covariance
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) pose.pose.covariance[idx[r] * 6 + idx[c]] = e.cov[r * 3 + c];
  pose_pub_.publish(pose);
  amcl_pose_pub_.publish(pose);

  publishQuality(stamp, filter);

  if (publish_tf_ && odom_pose) {
    // map -> odom = estimate (map -> base) composed with the inverse of odom -> base at the same
    // step; the carried pose gives the same, so it holds from `at` on.
    const Pose2D inv_odom = mcl::between(*odom_pose, {0, 0, 0});
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

  if (force_cloud || filter_stamp - last_cloud_ >= cloud_period_) {
    last_cloud_ = filter_stamp;
    // The particles are not carried forward: the cloud is dated by the applied odometry.
    publishCloud(ros::Time(filter_stamp), filter.particles());
    if (beacons && belts_pub_.getNumSubscribers() > 0) publishBelts(ros::Time(filter_stamp), *beacons, last_step);
  }
}

void LocalizationOutputs::publishCloud(const ros::Time& stamp, const mcl::ParticleSet& s) {
  if (cloud_pub_.getNumSubscribers() == 0 && amcl_cloud_pub_.getNumSubscribers() == 0) return;
  geometry_msgs::PoseArray cloud;
  cloud.header.stamp = stamp;
  cloud.header.frame_id = map_frame_;
  cloud.poses.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) cloud.poses.push_back(toMsg({s.x[i], s.y[i], s.theta[i]}));
  if (cloud_pub_.getNumSubscribers() > 0) cloud_pub_.publish(cloud);
  if (amcl_cloud_pub_.getNumSubscribers() > 0) amcl_cloud_pub_.publish(cloud);
}

void LocalizationOutputs::publishBelts(const ros::Time& stamp, const mcl::BeaconBelts& beacons, double last_step) {
  visualization_msgs::MarkerArray arr;
  const auto& cfg = beacons.config();
  const auto& latest = beacons.latest();
  for (std::size_t id = 0; id < latest.size(); ++id) {
    visualization_msgs::Marker m;
    m.header.stamp = stamp;
    m.header.frame_id = map_frame_;
    m.ns = "beacon_belts";
    m.id = static_cast<int>(id);
    const bool fresh = last_step - latest[id].stamp <= std::max(0.5, cfg.belt_max_age);
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

}  // namespace localization
}  // namespace hal_nodes
