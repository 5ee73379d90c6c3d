// What the Localization device publishes for each new odometry: /mcl/pose, /mcl/quality, tf
// map -> odom (REP-105), and at ~cloud_rate the particle cloud and the beacon belts for rviz.
// amcl's names beside ours, for the tools and scripts written for amcl: /amcl_pose (latched, as
// amcl's) is /mcl/pose, /particlecloud is /mcl/particlecloud.
#pragma once

#include <geometry_msgs/Pose.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include "hal_nodes/mcl/mcl.h"
#include "localization_config.h"

namespace hal_nodes {
namespace localization {

class LocalizationOutputs {
 public:
  LocalizationOutputs(ros::NodeHandle& nh, const LocalizationConfig& config);

  // `pose`: the filter's estimate carried to `at` (the newest odometry's stamp; carried_pose.h).
  // The filter itself stands at `filter_stamp` (the applied odometry's stamp), where `odom_pose`
  // is odom -> base_link, for map -> odom (none: no tf). `beacons` may be null; `last_step`
  // dates the belts.
  // `force_cloud`: the particle cloud now, whatever ~cloud_rate says (request_nomotion_update).
  void publish(double at, const mcl::Pose2D& pose, const mcl::Filter& filter, double filter_stamp,
               const mcl::Pose2D* odom_pose, const mcl::BeaconBelts* beacons, double last_step,
               bool force_cloud = false);

  // The particles on /mcl/particlecloud and /particlecloud (for those subscribed).
  void publishCloud(const ros::Time& stamp, const mcl::ParticleSet& set);
  // The filter's quality on /mcl/quality (publish() sends it with every estimate).
  void publishQuality(const ros::Time& stamp, const mcl::Filter& filter);

 private:
  // One circle per beacon whose latest range is recent: the belt the particles are weighed by.
  void publishBelts(const ros::Time& stamp, const mcl::BeaconBelts& beacons, double last_step);

  std::string map_frame_, odom_frame_;
  bool publish_tf_;
  double tf_tolerance_, cloud_period_;
  double last_cloud_ = -1e300;
  ros::Publisher pose_pub_, quality_pub_, cloud_pub_, belts_pub_, amcl_pose_pub_, amcl_cloud_pub_;
  tf2_ros::TransformBroadcaster tf_;
};

// A planar pose as a geometry_msgs/Pose (z = 0, yaw only).
geometry_msgs::Pose toMsg(const mcl::Pose2D& p);

}  // namespace localization
}  // namespace hal_nodes
