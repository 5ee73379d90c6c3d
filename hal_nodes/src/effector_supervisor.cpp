#include "hal_nodes/effector_supervisor.h"

#include <robot_core/command_gate.h>
#include <std_msgs/Bool.h>

namespace hal_nodes {

EffectorSupervisor::EffectorSupervisor(ros::NodeHandle nh) : nh_(nh) {
  state_pub_ = nh.advertise<std_msgs::Bool>("/effectors/deactivated", 1, true);
  std_msgs::Bool initial;
  initial.data = false;
  state_pub_.publish(initial);
  using Event = ros::ServiceEvent<std_srvs::Trigger::Request, std_srvs::Trigger::Response>;
  robot_core::CommandGate::instance();  // now: it must know the match before the first call
  // A caller outside the robot's network is refused during a match (robot_core/command_gate.h).
  auto gated = [](bool deactivate, EffectorSupervisor* self) {
    return [deactivate, self](Event& event) {
      const std::string what = deactivate ? "/effectors/deactivate" : "/effectors/activate";
      if (!robot_core::CommandGate::instance().accept(event.getCallerName(), what)) {
        event.getResponse().success = false;
        event.getResponse().message = "refused: " + event.getCallerName() + " is outside the robot's network and a match runs";
        return true;
      }
      return self->set(deactivate, event.getResponse());
    };
  };
  deactivate_srv_ = nh.advertiseService<Event>("/effectors/deactivate", boost::function<bool(Event&)>(gated(true, this)));
  activate_srv_ = nh.advertiseService<Event>("/effectors/activate", boost::function<bool(Event&)>(gated(false, this)));
  match_end_sub_ = nh.subscribe("/effectors/match_end", 1, &EffectorSupervisor::onMatchEnd, this);
}

bool EffectorSupervisor::set(bool deactivated, std_srvs::Trigger::Response& res) {
  std_msgs::Bool msg;
  msg.data = deactivated;
  state_pub_.publish(msg);
  res.success = true;
  res.message = deactivated ? "every effector deactivated" : "effectors active again";
  ROS_WARN("%s", res.message.c_str());
  return true;
}

void EffectorSupervisor::onMatchEnd(const std_msgs::Time& msg) {
  match_end_timer_.stop();
  if (msg.data.isZero()) return;  // disarmed
  const ros::Duration left = msg.data - ros::Time::now();
  ROS_INFO("effectors: the match ends at %.3f (in %.1f s): deactivating then if nobody has", msg.data.toSec(),
           left.toSec());
  // A one-shot timer on ROS time: the simulated match end at any real-time factor.
  match_end_timer_ = nh_.createTimer(
      std::max(left, ros::Duration(0.001)),
      [this](const ros::TimerEvent&) {
        std_srvs::Trigger::Response res;
        ROS_WARN("effectors: match end");
        set(true, res);
      },
      true);
}

}  // namespace hal_nodes
