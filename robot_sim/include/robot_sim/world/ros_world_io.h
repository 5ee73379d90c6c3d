// The world's ROS side, kept out of the models: reading its parameters and turning its state
// into messages (ground truth, elements, match, rviz markers).
#pragma once

#include <nav_msgs/Odometry.h>
#include <robot_sim/GameElements.h>
#include <robot_sim/MatchState.h>
#include <robot_sim/ScoreEvents.h>
#include <ros/ros.h>
#include <visualization_msgs/MarkerArray.h>

#include "robot_sim/world/config.h"
#include "robot_sim/world/sim_world.h"

namespace robot_sim {

// Reads `<pnh>/world` and the global `table`. Throws ConfigError.
WorldConfig loadWorldConfig(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);

nav_msgs::Odometry toOdometry(const BodyTruth& truth, const ros::Time& stamp, const std::string& child_frame);
GameElements toElementsMsg(const std::vector<GameElement>& elements, const ros::Time& stamp);
robot_sim::MatchState toMatchMsg(const MatchProgress& match, const std::string& year, const ros::Time& stamp);
robot_sim::ScoreEvents toScoreEventsMsg(const std::vector<RefereeEvent>& events, const ros::Time& stamp);

// Table, borders, beacons, start and scoring zones, opponent and elements, in `map`.
visualization_msgs::MarkerArray worldMarkers(const WorldConfig& config, const WorldSnapshot& snap,
                                             const ros::Time& stamp);

}  // namespace robot_sim
