// MotorBoard: the 2009 robot's CAN motor board, 2 H-bridges with quadrature encoders
// (protocol: motor_board_protocol.h).
//
// Parameters (besides the CANopen ones in canopen_board.h): read and described in readParams()
// (the table: hcl_drivers/PARAMETERS.md, make docs).
// Topics:
//   in   ~motor/<name>/command   hcl_drivers/MotorCommand, value = PWM duty in 1/1000 of full
//                                voltage (-1000..1000, clamped); older than ~command_timeout -> 0
//   out  ~encoder/<name>         hcl_drivers/EncoderCounter (32 bits), latched
//   out  ~state                  hcl_drivers/MotorBoardState, latched
// Every poll sends the command PDO (0 when stale), feeding the firmware's own 200 ms watchdog:
// the motors stop even when this driver dies.
#include <hcl_drivers/EncoderCounter.h>
#include <hcl_drivers/MotorBoardState.h>
#include <hcl_drivers/MotorCommand.h>

#include "canopen_board.h"
#include "hcl_drivers/board_nodelet.h"
#include "motor_board_protocol.h"

namespace hcl_drivers {

using robot_core::ParameterError;

class MotorBoard : public CanopenBoard {
 protected:
  void readParams(const robot_core::Params& p) override {
    p.describe("motors", "names of motor 0 and 1, e.g. [left, right] (required, 1..2 names)");
    const std::vector<std::string> motors = p.optionalStringList("motors");
    if (motors.empty() || motors.size() > motor_board::kMotors)
      throw ParameterError("parameter " + p.qualified("motors") + ": required, a list of 1..2 motor names");
    motors_ = motors;
    p.describe("encoders", "names of encoder 0 and 1 (1..2 names); when absent the motor names");
    encoders_ = p.optionalStringList("encoders", motors_);
    if (encoders_.empty() || encoders_.size() > motor_board::kMotors)
      throw ParameterError("parameter " + p.qualified("encoders") + ": a list of 1..2 encoder names");
    const uint32_t n = static_cast<uint32_t>(nodeId());
    command_cob_ = cobIdParam(p, "command_cob_id", canopen::kRpdo1 + n, "COB-ID of the RPDO with the PWM commands");
    encoder_cob_ = cobIdParam(p, "encoder_cob_id", canopen::kTpdo1 + n, "COB-ID of the TPDO with the encoder counters");
    status_cob_ = cobIdParam(p, "status_cob_id", canopen::kTpdo2 + n, "COB-ID of the TPDO with the applied PWM and flags");
    p.describe("watchdog_ms", "[ms] firmware watchdog written by SDO 0x2001 at configuration: no command, motors stop");
    watchdog_ms_ = p.optionalInt("watchdog_ms", 200);
    p.requireInRange("watchdog_ms", watchdog_ms_, 10, 1000);
  }

  void setup(BoardContext& ctx) override {
    node().onFrame(encoder_cob_, [this](const CanFrame& f) {
      const auto e = motor_board::decodeEncoders(f);
      if (!e) return false;
      std::lock_guard lk(mutex_);
      encoders_raw_ = e->raw;
      got_encoders_ = true;
      return true;
    });
    node().onFrame(status_cob_, [this](const CanFrame& f) {
      const auto s = motor_board::decodeStatus(f);
      if (!s) return false;
      std::lock_guard lk(mutex_);
      status_ = *s;
      got_status_ = true;
      return true;
    });

    state_pub_ = ctx.pnh.advertise<MotorBoardState>("state", 1, true);
    for (std::size_t i = 0; i < encoders_.size(); ++i)
      encoder_pubs_.push_back(ctx.pnh.advertise<EncoderCounter>("encoder/" + encoders_[i], 1, true));
    for (std::size_t i = 0; i < motors_.size(); ++i)
      subs_.push_back(subscribeCommand<MotorCommand>(ctx, "motor/" + motors_[i] + "/command",
                                                      [this, i](const MotorCommand::ConstPtr& m) { onCommand(i, *m); }));
  }

  std::vector<uint32_t> extraCobIds() const override { return {}; }

  void configureNode() override {
    node().sdoWrite(motor_board::kWatchdogIndex, 0, static_cast<uint32_t>(watchdog_ms_), 2, sdoTimeout());
    firmware_version_ = node().sdoRead(motor_board::kVersionIndex, 0, sdoTimeout());
  }

  bool exchange() override {
    const auto pwm = commandsToApply();
    if (!node().sendRaw(motor_board::encodeCommand(command_cob_, pwm))) {
      fail("sending the motor command: " + node().lastError());
      return false;
    }
    {
      std::lock_guard lk(mutex_);
      got_encoders_ = got_status_ = false;
      sent_ = pwm;
    }
    const bool answered = requestPdos({{encoder_cob_, 8}, {status_cob_, 5}},
                                      [this] {
                                        std::lock_guard lk(mutex_);
                                        return got_encoders_ && got_status_;
                                      },
                                      "motor board");
    if (!answered) return false;
    publishState();
    return true;
  }

  void stopActuators() override {
    {
      std::lock_guard lk(mutex_);
      for (auto& c : commands_) c = Command{};
    }
    node().sendRaw(motor_board::encodeCommand(command_cob_, {0, 0}));
  }

  void publishState() override {
    MotorBoardState::Ptr s(new MotorBoardState);
    s->header.stamp = ros::Time::now();
    fillStatus(s->node);
    std::lock_guard lk(mutex_);
    s->motor_names = motors_;
    s->encoder_names = encoders_;
    for (std::size_t i = 0; i < motors_.size(); ++i) {
      s->pwm_applied.push_back(status_.pwm[i]);
      s->pwm_commanded.push_back(sent_[i]);
    }
    for (std::size_t i = 0; i < encoders_.size(); ++i) s->encoder_raw.push_back(encoders_raw_[i]);
    s->watchdog_stopped = status_.watchdog_stopped;
    if (s->node.answering) {
      for (std::size_t i = 0; i < encoders_.size(); ++i) {
        EncoderCounter::Ptr e(new EncoderCounter);
        e->header.stamp = s->header.stamp;
        e->name = encoders_[i];
        e->raw = encoders_raw_[i];
        e->bits = 32;
        e->board_resets = s->node.boot_ups;
        encoder_pubs_[i].publish(e);
      }
    }
    state_pub_.publish(s);
  }

  void diagnoseBoard(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    std::lock_guard lk(mutex_);
    stat.add("firmware version", firmware_version_);
    stat.add("commands dropped as stale", stale_commands_);
    stat.add("firmware watchdog stopped motors", status_.watchdog_stopped);
    for (std::size_t i = 0; i < motors_.size(); ++i) stat.add("pwm sent " + motors_[i], sent_[i]);
  }

 private:
  struct Command {
    int16_t pwm = 0;
    ros::Time stamp, received;
  };

  void onCommand(std::size_t i, const MotorCommand& m) {
    if (!acceptCommand("motor")) return;
    std::lock_guard lk(mutex_);
    commands_[i].pwm = static_cast<int16_t>(std::max(-1000, std::min(1000, m.value)));
    commands_[i].stamp = m.header.stamp;
    commands_[i].received = ros::Time::now();
  }

  std::array<int16_t, motor_board::kMotors> commandsToApply() {
    std::lock_guard lk(mutex_);
    std::array<int16_t, motor_board::kMotors> pwm{0, 0};
    for (std::size_t i = 0; i < motors_.size(); ++i) {
      Command& c = commands_[i];
      if (c.received.isZero()) continue;
      if (!fresh(c.stamp, c.received)) {
        if (c.pwm != 0) {
          ++stale_commands_;
          ROS_WARN("%s: no fresh command for motor %s for %.2f s: stopping it", boardName().c_str(), motors_[i].c_str(),
                   commandTimeout());
        }
        c = Command{};
        continue;
      }
      pwm[i] = c.pwm;
    }
    return pwm;
  }

  std::vector<std::string> motors_, encoders_;
  uint32_t command_cob_ = 0, encoder_cob_ = 0, status_cob_ = 0;
  int watchdog_ms_ = 200;
  ros::Publisher state_pub_;
  std::vector<ros::Publisher> encoder_pubs_;
  std::vector<ros::Subscriber> subs_;

  robot_core::PriorityInheritanceMutex mutex_;
  std::array<Command, motor_board::kMotors> commands_{};
  std::array<int16_t, motor_board::kMotors> sent_{0, 0};
  std::array<uint32_t, motor_board::kMotors> encoders_raw_{0, 0};
  motor_board::Status status_;
  bool got_encoders_ = false, got_status_ = false;
  uint32_t firmware_version_ = 0;
  unsigned long stale_commands_ = 0;
};

}  // namespace hcl_drivers

HCL_EXPORT_BOARD(MotorBoard,
                 "CAN motor board: 2 PWM H-bridges, 2 32-bit encoder counters (CANopen PDOs).")
