// StepperBoard: the 2009 robot's CAN stepper board, 2 steppers with min/max end switches
// (protocol: stepper_board_protocol.h).
//
// Parameters (besides the CANopen ones in canopen_board.h): read and described in readParams()
// (the table: hcl_drivers/PARAMETERS.md, make docs).
// Topics:
//   in   ~stepper/<name>/target  std_msgs/Int32, absolute target [steps]; refused while the board
//                                does not answer. A target is a position, not a speed: it does not
//                                go stale, but halt() (shutdown, board stale) re-targets every
//                                stepper to where it is, so nothing moves after a fault.
//   out  ~inputs                 hcl_drivers/DigitalInputs: end switches, latched
//   out  ~state                  hcl_drivers/StepperBoardState, latched
// Until a stepper is given a target, the driver sends its current position (never a move).
#include <hcl_drivers/DigitalInputs.h>
#include <hcl_drivers/StepperBoardState.h>
#include <std_msgs/Int32.h>

#include "canopen_board.h"
#include "hcl_drivers/board_nodelet.h"
#include "stepper_board_protocol.h"

namespace hcl_drivers {

using robot_core::ParameterError;

class StepperBoard : public CanopenBoard {
 protected:
  void readParams(const robot_core::Params& p) override {
    p.describe("steppers", "names of stepper 0 and 1 (required, 1..2 names)");
    steppers_ = p.optionalStringList("steppers");
    if (steppers_.empty() || steppers_.size() > stepper_board::kSteppers)
      throw ParameterError("parameter " + p.qualified("steppers") + ": required, a list of 1..2 stepper names");
    std::vector<std::string> defaults;
    for (const auto& s : steppers_) {
      defaults.push_back(s + "_min");
      defaults.push_back(s + "_max");
    }
    p.describe("end_switches", "names of the end switches in bit order; when absent <stepper>_min, <stepper>_max each");
    switch_names_ = p.optionalStringList("end_switches", defaults);
    const uint32_t n = static_cast<uint32_t>(nodeId());
    target_cob_ = cobIdParam(p, "target_cob_id", canopen::kRpdo1 + n, "COB-ID of the RPDO with the stepper targets");
    position_cob_ = cobIdParam(p, "position_cob_id", canopen::kTpdo1 + n, "COB-ID of the TPDO with the stepper positions");
    switch_cob_ = cobIdParam(p, "switch_cob_id", canopen::kTpdo2 + n, "COB-ID of the TPDO with the end switches");
  }

  void setup(BoardContext& ctx) override {
    node().onFrame(position_cob_, [this](const CanFrame& f) {
      const auto p = stepper_board::decodePositions(f);
      if (!p) return false;
      std::lock_guard lk(mutex_);
      position_ = *p;
      got_position_ = true;
      return true;
    });
    node().onFrame(switch_cob_, [this](const CanFrame& f) {
      const auto s = stepper_board::decodeSwitches(f);
      if (!s) return false;
      std::lock_guard lk(mutex_);
      switches_ = *s;
      got_switches_ = true;
      return true;
    });
    state_pub_ = ctx.pnh.advertise<StepperBoardState>("state", 1, true);
    inputs_pub_ = ctx.pnh.advertise<DigitalInputs>("inputs", 1, true);
    for (std::size_t i = 0; i < steppers_.size(); ++i)
      subs_.push_back(subscribeCommand<std_msgs::Int32>(ctx, "stepper/" + steppers_[i] + "/target",
                                                         [this, i](const std_msgs::Int32::ConstPtr& m) {
                                                           if (!acceptCommand("stepper target")) return;
                                                           std::lock_guard lk(mutex_);
                                                           target_[i] = m->data;
                                                           commanded_[i] = true;
                                                         }));
  }

  bool exchange() override {
    {
      std::lock_guard lk(mutex_);
      got_position_ = got_switches_ = false;
    }
    const bool answered = requestPdos({{position_cob_, 8}, {switch_cob_, 2}},
                                      [this] {
                                        std::lock_guard lk(mutex_);
                                        return got_position_ && got_switches_;
                                      },
                                      "stepper board");
    if (!answered) return false;
    std::array<int32_t, stepper_board::kSteppers> t{};
    bool any = false;
    {
      std::lock_guard lk(mutex_);
      for (int i = 0; i < stepper_board::kSteppers; ++i) {
        t[i] = commanded_[i] ? target_[i] : position_[i];
        any = any || commanded_[i];
      }
      sent_ = t;
    }
    if (any && !node().sendRaw(stepper_board::encodeTargets(target_cob_, t))) {
      fail("sending the targets: " + node().lastError());
      return false;
    }
    publishState();
    return true;
  }

  void stopActuators() override {
    std::array<int32_t, stepper_board::kSteppers> t{};
    {
      std::lock_guard lk(mutex_);
      t = position_;
      for (int i = 0; i < stepper_board::kSteppers; ++i) {
        commanded_[i] = false;
        target_[i] = position_[i];
      }
      sent_ = t;
    }
    node().sendRaw(stepper_board::encodeTargets(target_cob_, t));
  }

  void publishState() override {
    StepperBoardState::Ptr s(new StepperBoardState);
    s->header.stamp = ros::Time::now();
    fillStatus(s->node);
    std::lock_guard lk(mutex_);
    s->stepper_names = steppers_;
    for (std::size_t i = 0; i < steppers_.size(); ++i) {
      s->position.push_back(position_[i]);
      s->target.push_back(sent_[i]);
      s->moving.push_back((switches_.moving >> i) & 1);
    }
    s->end_switches = switches_.end_switches;
    if (s->node.answering) {
      DigitalInputs::Ptr in(new DigitalInputs);
      in->header.stamp = s->header.stamp;
      in->bits = switches_.end_switches;
      in->names = switch_names_;
      inputs_pub_.publish(in);
    }
    state_pub_.publish(s);
  }

 private:
  std::vector<std::string> steppers_, switch_names_;
  uint32_t target_cob_ = 0, position_cob_ = 0, switch_cob_ = 0;
  ros::Publisher state_pub_, inputs_pub_;
  std::vector<ros::Subscriber> subs_;

  robot_core::PriorityInheritanceMutex mutex_;
  std::array<int32_t, stepper_board::kSteppers> position_{0, 0}, target_{0, 0}, sent_{0, 0};
  std::array<bool, stepper_board::kSteppers> commanded_{false, false};
  stepper_board::Switches switches_;
  bool got_position_ = false, got_switches_ = false;
};

}  // namespace hcl_drivers

HCL_EXPORT_BOARD(StepperBoard,
                 "CAN stepper board: 2 steppers with position targets, min/max end switches.")
