// Epos: a Maxon EPOS motor controller (CANopen DS-402) in profile velocity mode
// (protocol and PDO mapping: epos_protocol.h).
//
// Parameters (besides the CANopen ones in canopen_board.h): read and described in readParams()
// (the table: hcl_drivers/PARAMETERS.md, make docs).
// Topics / services:
//   in   ~motor/<motor>/command   hcl_drivers/MotorCommand, value = target velocity [rpm];
//                                 older than ~command_timeout -> 0 rpm
//   out  ~encoder/<encoder>       hcl_drivers/EncoderCounter (position actual, 32 bits), latched
//   out  ~state                   hcl_drivers/EposState, latched
//   srv  ~enable                  std_srvs/SetBool: power stage on (DS-402 sequence) / off
//   srv  ~fault_reset             std_srvs/Trigger: one fault-reset controlword (faults are never reset automatically)
// Both services answer success=false with the reason while the drive does not answer.
#include <hcl_drivers/EncoderCounter.h>
#include <hcl_drivers/EposState.h>
#include <hcl_drivers/MotorCommand.h>
#include <std_srvs/SetBool.h>
#include <std_srvs/Trigger.h>

#include "canopen_board.h"
#include "epos_protocol.h"
#include "hcl_drivers/board_nodelet.h"

namespace hcl_drivers {

class Epos : public CanopenBoard {
 protected:
  void readParams(const robot_core::Params& p) override {
    p.describe("motor", "the motor's name, e.g. left: the command topic is ~motor/<motor>/command");
    motor_ = p.requireString("motor");
    p.describe("encoder", "the encoder's name: the counter topic is ~encoder/<encoder>; when absent the motor's");
    encoder_ = p.optionalString("encoder", motor_);
    p.describe("max_rpm", "[rpm] velocity commands are clamped to +-max_rpm");
    max_rpm_ = p.requireInt("max_rpm");
    p.requirePositive("max_rpm", max_rpm_);
    p.describe("enable_at_start", "request enable (power stage on) as soon as the drive answers");
    enable_requested_ = p.optionalBool("enable_at_start", false);
    const uint32_t n = static_cast<uint32_t>(nodeId());
    command_cob_ = cobIdParam(p, "command_cob_id", canopen::kRpdo1 + n,
                              "COB-ID of the RPDO with the controlword and target velocity");
    status_cob_ = cobIdParam(p, "status_cob_id", canopen::kTpdo1 + n,
                             "COB-ID of the TPDO with the statusword, mode and error code");
    feedback_cob_ = cobIdParam(p, "feedback_cob_id", canopen::kTpdo2 + n,
                               "COB-ID of the TPDO with position and velocity (EPOS often map it elsewhere: set it)");
  }

  void setup(BoardContext& ctx) override {
    const uint32_t n = static_cast<uint32_t>(nodeId());
    if (canopen::nodeOf(feedback_cob_) != n || canopen::nodeOf(status_cob_) != n)
      ROS_INFO("%s: EPOS PDOs mapped outside the node's COB-IDs (status 0x%03X, feedback 0x%03X)",
               ctx.name.c_str(), status_cob_, feedback_cob_);

    node().onFrame(status_cob_, [this](const CanFrame& f) {
      const auto s = epos::decodeStatus(f);
      if (!s) return false;
      std::lock_guard lk(mutex_);
      status_ = *s;
      got_status_ = true;
      return true;
    });
    node().onFrame(feedback_cob_, [this](const CanFrame& f) {
      const auto fb = epos::decodeFeedback(f);
      if (!fb) return false;
      std::lock_guard lk(mutex_);
      feedback_ = *fb;
      got_feedback_ = true;
      return true;
    });
    state_pub_ = ctx.pnh.advertise<EposState>("state", 1, true);
    encoder_pub_ = ctx.pnh.advertise<EncoderCounter>("encoder/" + encoder_, 1, true);
    command_sub_ = subscribeCommand<MotorCommand>(ctx, "motor/" + motor_ + "/command", [this](const MotorCommand::ConstPtr& m) {
      if (!acceptCommand("velocity")) return;
      std::lock_guard lk(mutex_);
      command_rpm_ = std::max(-max_rpm_, std::min(max_rpm_, m->value));
      command_stamp_ = m->header.stamp;
      command_received_ = ros::Time::now();
    });
    enable_srv_ = ctx.pnh.advertiseService<std_srvs::SetBool::Request, std_srvs::SetBool::Response>(
        "enable", [this](std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res) {
          if (req.data && !acceptCommand("enable")) {
            res.success = false;
            res.message = "EPOS (node " + std::to_string(nodeId()) + ") not answering: " + lastError();
            return true;
          }
          std::lock_guard lk(mutex_);
          enable_requested_ = req.data;
          res.success = true;
          res.message = req.data ? "enabling" : "disabled";
          return true;
        });
    fault_reset_srv_ = ctx.pnh.advertiseService<std_srvs::Trigger::Request, std_srvs::Trigger::Response>(
        "fault_reset", [this](std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
          if (!acceptCommand("fault reset")) {
            res.success = false;
            res.message = "EPOS (node " + std::to_string(nodeId()) + ") not answering: " + lastError();
            return true;
          }
          std::lock_guard lk(mutex_);
          fault_reset_pending_ = true;
          res.success = true;
          res.message = "fault reset sent with the next poll";
          return true;
        });
  }

  void configureNode() override {
    node().sdoWrite(epos::kModesOfOperation, 0, static_cast<uint8_t>(epos::kProfileVelocityMode), 1, sdoTimeout());
  }

  bool exchange() override {
    {
      std::lock_guard lk(mutex_);
      got_status_ = got_feedback_ = false;
    }
    const bool answered = requestPdos({{status_cob_, 5}, {feedback_cob_, 8}},
                                      [this] {
                                        std::lock_guard lk(mutex_);
                                        return got_status_ && got_feedback_;
                                      },
                                      "EPOS");
    if (!answered) return false;
    uint16_t cw = 0;
    int32_t rpm = 0;
    {
      std::lock_guard lk(mutex_);
      const auto ds = epos::decodeDriveState(status_.statusword);
      if (fault_reset_pending_) {
        cw = epos::kCwFaultReset;
        fault_reset_pending_ = false;
      } else {
        cw = epos::nextControlword(ds, enable_requested_);
      }
      if (!command_received_.isZero() && !fresh(command_stamp_, command_received_)) {
        if (command_rpm_ != 0)
          ROS_WARN("%s: no fresh velocity command for %.2f s: 0 rpm", boardName().c_str(), commandTimeout());
        ++stale_commands_;
        command_rpm_ = 0;
        command_received_ = ros::Time();
      }
      rpm = ds == epos::DriveState::kOperationEnabled ? command_rpm_ : 0;
      sent_cw_ = cw;
      sent_rpm_ = rpm;
    }
    if (!node().sendRaw(epos::encodeCommand(command_cob_, cw, rpm))) {
      fail("sending the command: " + node().lastError());
      return false;
    }
    publishState();
    return true;
  }

  void stopActuators() override {
    {
      std::lock_guard lk(mutex_);
      command_rpm_ = 0;
      command_received_ = ros::Time();
      sent_rpm_ = 0;
      sent_cw_ = epos::kCwShutdown;
    }
    // 0 rpm and shutdown (power stage off) in one PDO.
    node().sendRaw(epos::encodeCommand(command_cob_, epos::kCwShutdown, 0));
  }

  void publishState() override {
    EposState::Ptr s(new EposState);
    s->header.stamp = ros::Time::now();
    fillStatus(s->node);
    std::lock_guard lk(mutex_);
    const auto ds = epos::decodeDriveState(status_.statusword);
    s->statusword = status_.statusword;
    s->drive_state = epos::toString(ds);
    s->mode_display = status_.mode_display;
    s->error_code = status_.error_code;
    s->fault = ds == epos::DriveState::kFault || ds == epos::DriveState::kFaultReaction;
    s->enable_requested = enable_requested_;
    s->position = feedback_.position;
    s->velocity_rpm = feedback_.velocity_rpm;
    s->target_rpm = sent_rpm_;
    if (s->node.answering) {
      EncoderCounter::Ptr e(new EncoderCounter);
      e->header.stamp = s->header.stamp;
      e->name = encoder_;
      e->raw = static_cast<uint32_t>(feedback_.position);
      e->bits = 32;
      e->board_resets = s->node.boot_ups;
      encoder_pub_.publish(e);
    }
    state_pub_.publish(s);
  }

  void diagnoseBoard(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    std::lock_guard lk(mutex_);
    const auto ds = epos::decodeDriveState(status_.statusword);
    stat.add("drive state", epos::toString(ds));
    stat.addf("error code", "0x%04X", status_.error_code);
    stat.add("enable requested", enable_requested_);
    stat.addf("controlword sent", "0x%04X", sent_cw_);
    stat.add("target rpm sent", sent_rpm_);
    stat.add("commands dropped as stale", stale_commands_);
    if (ds == epos::DriveState::kFault) stat.mergeSummary(diagnostic_msgs::DiagnosticStatus::ERROR, "EPOS in fault");
  }

 private:
  std::string motor_, encoder_;
  int max_rpm_ = 0;
  uint32_t command_cob_ = 0, status_cob_ = 0, feedback_cob_ = 0;
  ros::Publisher state_pub_, encoder_pub_;
  ros::Subscriber command_sub_;
  ros::ServiceServer enable_srv_, fault_reset_srv_;

  robot_core::PriorityInheritanceMutex mutex_;
  epos::Status status_;
  epos::Feedback feedback_;
  bool got_status_ = false, got_feedback_ = false;
  bool enable_requested_ = false, fault_reset_pending_ = false;
  int32_t command_rpm_ = 0;
  ros::Time command_stamp_, command_received_;
  uint16_t sent_cw_ = 0;
  int32_t sent_rpm_ = 0;
  unsigned long stale_commands_ = 0;
};

}  // namespace hcl_drivers

HCL_EXPORT_BOARD(Epos,
                 "Maxon EPOS DS-402 drive: enable, profile velocity [rpm], position/velocity actual, fault state.")
