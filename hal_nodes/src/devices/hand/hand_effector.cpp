// Hand: the 2009 robot's column gripper. Two servo fingers (servo board, pulse widths) and a
// stepper lift (stepper board, absolute targets in steps, end switches), offered as one
// preemptible action hal_nodes/Hand on this device's name (/hal/hand): OPEN, CLOSE, LIFT to
// a height. Servos have no feedback, so a finger move succeeds after ~finger_time; a lift
// succeeds when the stepper is within ~tolerance_steps of its target and stopped, and aborts
// when it stops elsewhere (an end switch, a jam) or after ~timeout. A cancel or a
// deactivation stops the lift where it is (re-targets it to its position) and leaves the
// fingers as they are (a held column stays held); while deactivated goals are refused.
// With ~holding_sensor (a switch that sees an element in the hand), the action's feedback and
// result say `holding`, and ~holding (std_msgs/Bool, latched) follows it, so a strategy counts
// what it holds, not what it tried.
//
// Parameters: read and described in configure() (the table: hal_nodes/PARAMETERS.md, make docs).
#include <actionlib/server/simple_action_server.h>
#include <hal_nodes/HandAction.h>
#include <hcl_drivers/StepperBoardState.h>
#include <std_msgs/Bool.h>
#include <std_msgs/Int32.h>
#include <std_msgs/UInt16.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "hal_nodes/devices/contact_input.h"
#include "hal_nodes/device_nodelet.h"
#include <robot_core/params.h>

namespace hal_nodes {

class HandEffector : public Effector {
 public:
  void configure(const robot_core::Params& params) override {
    fingers_.clear();
    params.describe("fingers", "the servo fingers by name (at least one): {topic, open_us, closed_us} each");
    for (const auto& name : params.requireBlockNames("fingers")) {
      const robot_core::Params p = params.block("fingers/" + name);
      Finger f;
      p.describe("open_us", "[us] the servo's pulse width with the finger open");
      f.open_us = p.requireInt("open_us");
      p.describe("closed_us", "[us] the servo's pulse width with the finger closed");
      f.closed_us = p.requireInt("closed_us");
      p.requireInRange("open_us", f.open_us, 500, 2500);
      p.requireInRange("closed_us", f.closed_us, 500, 2500);
      p.describe("topic", "the servo's pulse topic out (std_msgs/UInt16 [us])");
      f.topic = p.requireString("topic");
      fingers_.push_back(std::move(f));
    }
    params.describe("finger_time", "[s] a finger move succeeds after this (servos have no feedback)");
    finger_time_ = params.optionalDouble("finger_time", 0.6);
    params.requirePositive("finger_time", finger_time_);
    const robot_core::Params lift = params["lift"];
    lift.describe("target", "the lift stepper's target topic out (std_msgs/Int32, absolute steps)");
    lift_target_topic_ = lift.requireString("target");
    lift.describe("stepper", "the lift stepper's name in the board's state");
    stepper_ = lift.requireString("stepper");
    lift.describe("steps_per_meter", "[steps/m] the lift's stepper steps per metre of height");
    steps_per_meter_ = lift.requireDouble("steps_per_meter");
    lift.requirePositive("steps_per_meter", steps_per_meter_);
    lift.describe("max_height", "[m] the highest lift goal accepted");
    max_height_ = lift.requireDouble("max_height");
    lift.requirePositive("max_height", max_height_);
    params.describe("tolerance_steps", "[steps] a lift succeeds stopped this close to its target");
    tolerance_ = params.optionalInt("tolerance_steps", 5);
    params.requireInRange("tolerance_steps", tolerance_, 0, 1000);
    params.describe("timeout", "[s] a goal not done by then aborts (the lift stops where it is)");
    timeout_ = params.optionalDouble("timeout", 8.0);
    params.requirePositive("timeout", timeout_);
    params.describe("max_input_age", "[s] an older stepper board state (or holding sensor) is stale");
    max_input_age_ = params.optionalDouble("max_input_age", 0.5);
    params.requirePositive("max_input_age", max_input_age_);
    lift.describe("state", "the stepper board's state topic in (hcl_drivers/StepperBoardState)");
    lift_state_topic_ = lift.requireString("state");
    holding_sensor_.reset();
    params.describe("holding_sensor", "a switch that sees an element in the hand (contact_input.h); optional");
    if (params.has("holding_sensor")) holding_sensor_ = ContactSpec::read(params, "holding_sensor");
  }

  void init(DeviceContext& ctx) override {
    using namespace hcl_drivers;  // the boards' messages
    for (Finger& f : fingers_) f.pub = ctx.nh.advertise<std_msgs::UInt16>(f.topic, 1, true);
    lift_pub_ = ctx.nh.advertise<std_msgs::Int32>(lift_target_topic_, 1, true);
    state_ = addInput<StepperBoardState>(ctx.nh, lift_state_topic_, "stepper board");
    if (holding_sensor_) {
      holding_input_ = addInput<DigitalInputs>(ctx.nh, holding_sensor_->topic, "holding sensor");
      holding_pub_ = ctx.pnh.advertise<std_msgs::Bool>("holding", 1, true);
    }
    // Goals and cancels are polled in refresh(): everything happens on the refresh path, so
    // deactivation, goals and progress never race (latency: one refresh period).
    server_ = std::make_unique<actionlib::SimpleActionServer<HandAction>>(ctx.nh, ctx.name, false);
    server_->start();
  }

  void refresh() override {
    if (server_->isNewGoalAvailable()) {
      if (server_->isActive() && goal_.command == HandGoal::LIFT) stopLift();
      startGoal();
    } else if (server_->isActive() && server_->isPreemptRequested()) {
      if (goal_.command == HandGoal::LIFT) stopLift();
      server_->setPreempted(HandResult(), "preempted");
    }
    const auto pos = liftPosition();
    holding_ = readHolding();
    if (!pos) setUnavailable("no fresh state of lift stepper '" + stepper_ + "' (age " + std::to_string(state_->age()) + " s)");
    else if (holding_sensor_ && holding_ == HandResult::HOLDING_UNKNOWN)
      setUnavailable("no fresh holding sensor on " + holding_sensor_->topic);
    else setAvailable();
    if (!server_->isActive()) return;
    const double elapsed = (ros::Time::now() - goal_start_).toSec();
    HandFeedback fb;
    fb.height = pos ? pos->first / steps_per_meter_ : NAN;
    fb.holding = holding_;
    if (goal_.command == HandGoal::LIFT) {
      fb.state = "lifting";
      server_->publishFeedback(fb);
      if (!pos) return finish(false, "lift stepper state lost");
      if (std::abs(pos->first - target_steps_) <= tolerance_ && !pos->second) return finish(true, "at height");
      if (!pos->second && elapsed > 0.5) return finish(false, "lift stopped at " + std::to_string(fb.height) + " m (end switch or jam)");
    } else {
      fb.state = goal_.command == HandGoal::OPEN ? "opening" : "closing";
      server_->publishFeedback(fb);
      if (elapsed >= finger_time_) return finish(true, goal_.command == HandGoal::OPEN ? "open" : "closed");
    }
    if (elapsed > timeout_) {
      stopLift();
      finish(false, "timed out");
    }
  }

  void deactivate() override {
    stopLift();
    if (server_->isActive()) server_->setAborted(HandResult(), "deactivated");
  }

  void halt() override { deactivate(); }

 private:
  struct Finger {
    int open_us = 1500, closed_us = 1500;
    std::string topic;
    ros::Publisher pub;
  };

  // (position [steps], moving) of the lift stepper, if fresh.
  std::optional<std::pair<int, bool>> liftPosition() const {
    const auto s = state_->fresh(max_input_age_);
    if (!s) return std::nullopt;
    const auto it = std::find(s->stepper_names.begin(), s->stepper_names.end(), stepper_);
    const std::size_t i = it - s->stepper_names.begin();
    if (it == s->stepper_names.end() || i >= s->position.size()) return std::nullopt;
    return std::make_pair(static_cast<int>(s->position[i]), i < s->moving.size() && s->moving[i]);
  }

  void startGoal() {
    goal_ = *server_->acceptNewGoal();
    goal_start_ = ros::Time::now();
    if (!active()) return finish(false, "deactivated: effectors are frozen");
    if (goal_.command == HandGoal::OPEN || goal_.command == HandGoal::CLOSE) {
      for (auto& f : fingers_) {
        std_msgs::UInt16 m;
        m.data = static_cast<uint16_t>(goal_.command == HandGoal::OPEN ? f.open_us : f.closed_us);
        f.pub.publish(m);
      }
    } else if (goal_.command == HandGoal::LIFT) {
      if (!std::isfinite(goal_.height) || goal_.height < 0.0 || goal_.height > max_height_)
        return finish(false, "height must be 0.." + std::to_string(max_height_) + " m");
      if (!liftPosition()) return finish(false, "lift stepper state not available");
      target_steps_ = static_cast<int>(std::lround(goal_.height * steps_per_meter_));
      std_msgs::Int32 m;
      m.data = target_steps_;
      lift_pub_.publish(m);
    } else {
      finish(false, "unknown command " + std::to_string(goal_.command) + " (OPEN=0, CLOSE=1, LIFT=2)");
    }
  }

  void stopLift() {
    if (const auto pos = liftPosition()) {
      std_msgs::Int32 m;
      m.data = pos->first;
      lift_pub_.publish(m);
    }
  }

  // 1 / 0 from the holding sensor (published on ~holding when it changes), else HOLDING_UNKNOWN.
  int8_t readHolding() {
    if (!holding_sensor_) return HandResult::HOLDING_UNKNOWN;
    const auto m = holding_input_->fresh(max_input_age_);
    const auto closed = m ? holding_sensor_->closed(*m) : std::nullopt;
    if (!closed) return HandResult::HOLDING_UNKNOWN;
    const int8_t now = *closed ? 1 : 0;
    if (now != holding_) {
      std_msgs::Bool b;
      b.data = *closed;
      holding_pub_.publish(b);
    }
    return now;
  }

  void finish(bool ok, const std::string& message) {
    HandResult r;
    r.success = ok;
    r.message = message;
    r.holding = holding_;
    if (ok) server_->setSucceeded(r, message);
    else server_->setAborted(r, message);
  }

  std::vector<Finger> fingers_;
  std::unique_ptr<actionlib::SimpleActionServer<HandAction>> server_;
  std::shared_ptr<LatestValue<hcl_drivers::StepperBoardState>> state_;
  ros::Publisher lift_pub_;
  HandGoal goal_;
  ros::Time goal_start_;
  std::string stepper_, lift_target_topic_, lift_state_topic_;
  double steps_per_meter_ = 1.0, max_height_ = 0.0, finger_time_ = 0.6, timeout_ = 8.0, max_input_age_ = 0.5;
  int tolerance_ = 5, target_steps_ = 0;
  std::optional<ContactSpec> holding_sensor_;
  std::shared_ptr<LatestValue<hcl_drivers::DigitalInputs>> holding_input_;
  ros::Publisher holding_pub_;
  int8_t holding_ = HandResult::HOLDING_UNKNOWN;
};

}  // namespace hal_nodes

HAL_EXPORT_DEVICE(HandEffector, Hand,
                  "2009 hand: servo fingers and stepper lift as the preemptible hal_nodes/Hand action.")
