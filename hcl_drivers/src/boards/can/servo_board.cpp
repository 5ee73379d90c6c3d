// ServoBoard: the 2009 robot's CAN servo board: 4 RC servos, 4 SHARP GP2D12 rangers on its ADC,
// 16 switches (protocol and ranger curve: servo_board_protocol.h).
//
// Parameters (besides the CANopen ones in canopen_board.h): read and described in readParams()
// (the table: hcl_drivers/PARAMETERS.md, make docs).
// Topics:
//   in   ~servo/<name>/pulse_us  std_msgs/UInt16, pulse width 500..2500 us (0 = servo off); out of
//                                range values are counted and ignored. A servo holds its position
//                                (no timeout); halt() switches every servo off (no pulses).
//   out  ~range/<name>           sensor_msgs/Range [m] (frame_id = name), latched
//   out  ~inputs                 hcl_drivers/DigitalInputs (switches), latched
//   out  ~state                  hcl_drivers/ServoBoardState, latched
#include <hcl_drivers/DigitalInputs.h>
#include <hcl_drivers/ServoBoardState.h>
#include <sensor_msgs/Range.h>
#include <std_msgs/UInt16.h>

#include "canopen_board.h"
#include "hcl_drivers/board_nodelet.h"
#include "servo_board_protocol.h"

namespace hcl_drivers {

using robot_core::ParameterError;

class ServoBoard : public CanopenBoard {
 protected:
  void readParams(const robot_core::Params& p) override {
    p.describe("servos", "names of servo channels 0..3 in order (up to 4)");
    servos_ = p.optionalStringList("servos");
    p.describe("rangers", "names of ADC channels 0..3 with a GP2D12 ranger (up to 4)");
    rangers_ = p.optionalStringList("rangers");
    p.describe("switches", "names of switch inputs 0..15 in bit order (up to 16)");
    switch_names_ = p.optionalStringList("switches");
    if (servos_.size() > servo_board::kServos)
      throw ParameterError("parameter " + p.qualified("servos") + ": at most 4 servo names");
    if (rangers_.size() > servo_board::kAdcs)
      throw ParameterError("parameter " + p.qualified("rangers") + ": at most 4 ranger names");
    if (switch_names_.size() > 16)
      throw ParameterError("parameter " + p.qualified("switches") + ": at most 16 switch names");
    const uint32_t n = static_cast<uint32_t>(nodeId());
    servo_cob_ = cobIdParam(p, "servo_cob_id", canopen::kRpdo1 + n, "COB-ID of the RPDO with the servo pulse widths");
    ranger_cob_ = cobIdParam(p, "ranger_cob_id", canopen::kTpdo1 + n, "COB-ID of the TPDO with the ranger ADC values");
    switch_cob_ = cobIdParam(p, "switch_cob_id", canopen::kTpdo2 + n, "COB-ID of the TPDO with the switches");
  }

  void setup(BoardContext& ctx) override {
    node().onFrame(ranger_cob_, [this](const CanFrame& f) {
      const auto a = servo_board::decodeRangers(f);
      if (!a) return false;
      std::lock_guard lk(mutex_);
      adc_ = *a;
      got_adc_ = true;
      return true;
    });
    node().onFrame(switch_cob_, [this](const CanFrame& f) {
      const auto s = servo_board::decodeSwitches(f);
      if (!s) return false;
      std::lock_guard lk(mutex_);
      switches_ = *s;
      got_switches_ = true;
      return true;
    });
    state_pub_ = ctx.pnh.advertise<ServoBoardState>("state", 1, true);
    inputs_pub_ = ctx.pnh.advertise<DigitalInputs>("inputs", 1, true);
    for (const auto& r : rangers_) range_pubs_.push_back(ctx.pnh.advertise<sensor_msgs::Range>("range/" + r, 1, true));
    for (std::size_t i = 0; i < servos_.size(); ++i)
      subs_.push_back(subscribeCommand<std_msgs::UInt16>(ctx, "servo/" + servos_[i] + "/pulse_us",
                                                          [this, i](const std_msgs::UInt16::ConstPtr& m) {
                                                            if (!acceptCommand("servo")) return;
                                                            std::lock_guard lk(mutex_);
                                                            if (!servo_board::validPulse(m->data)) {
                                                              ++bad_commands_;
                                                              return;
                                                            }
                                                            pulse_[i] = m->data;
                                                          }));
  }

  bool exchange() override {
    std::array<uint16_t, servo_board::kServos> pulse{};
    {
      std::lock_guard lk(mutex_);
      pulse = pulse_;
      got_adc_ = got_switches_ = false;
    }
    if (!node().sendRaw(servo_board::encodeServos(servo_cob_, pulse))) {
      fail("sending the servo positions: " + node().lastError());
      return false;
    }
    const bool answered = requestPdos({{ranger_cob_, 8}, {switch_cob_, 2}},
                                      [this] {
                                        std::lock_guard lk(mutex_);
                                        return got_adc_ && got_switches_;
                                      },
                                      "servo board");
    if (!answered) return false;
    publishState();
    return true;
  }

  void stopActuators() override {
    {
      std::lock_guard lk(mutex_);
      pulse_.fill(0);
    }
    node().sendRaw(servo_board::encodeServos(servo_cob_, {0, 0, 0, 0}));
  }

  void publishState() override {
    ServoBoardState::Ptr s(new ServoBoardState);
    s->header.stamp = ros::Time::now();
    fillStatus(s->node);
    std::lock_guard lk(mutex_);
    s->servo_names = servos_;
    for (std::size_t i = 0; i < servos_.size(); ++i) s->servo_pulse_us.push_back(pulse_[i]);
    s->ranger_names = rangers_;
    for (std::size_t i = 0; i < rangers_.size(); ++i) {
      s->ranger_raw.push_back(adc_[i]);
      s->ranger_m.push_back(static_cast<float>(servo_board::gp2d12Metres(adc_[i])));
    }
    s->switches = switches_;
    if (s->node.answering) {
      for (std::size_t i = 0; i < rangers_.size(); ++i) {
        sensor_msgs::Range::Ptr r(new sensor_msgs::Range);
        r->header.stamp = s->header.stamp;
        r->header.frame_id = rangers_[i];
        r->radiation_type = sensor_msgs::Range::INFRARED;
        r->field_of_view = 0.08f;  // GP2D12: a narrow beam, ~5 degrees
        r->min_range = static_cast<float>(servo_board::kMinRange);
        r->max_range = static_cast<float>(servo_board::kMaxRange);
        r->range = s->ranger_m[i];
        range_pubs_[i].publish(r);
      }
      DigitalInputs::Ptr in(new DigitalInputs);
      in->header.stamp = s->header.stamp;
      in->bits = switches_;
      in->names = switch_names_;
      inputs_pub_.publish(in);
    }
    state_pub_.publish(s);
  }

  void diagnoseBoard(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    std::lock_guard lk(mutex_);
    stat.add("out-of-range servo commands", bad_commands_);
  }

 private:
  std::vector<std::string> servos_, rangers_, switch_names_;
  uint32_t servo_cob_ = 0, ranger_cob_ = 0, switch_cob_ = 0;
  ros::Publisher state_pub_, inputs_pub_;
  std::vector<ros::Publisher> range_pubs_;
  std::vector<ros::Subscriber> subs_;

  robot_core::PriorityInheritanceMutex mutex_;
  std::array<uint16_t, servo_board::kServos> pulse_{0, 0, 0, 0};
  std::array<uint16_t, servo_board::kAdcs> adc_{0, 0, 0, 0};
  uint16_t switches_ = 0;
  bool got_adc_ = false, got_switches_ = false;
  unsigned long bad_commands_ = 0;
};

}  // namespace hcl_drivers

HCL_EXPORT_BOARD(ServoBoard,
                 "CAN servo board: 4 RC servos, 4 SHARP GP2D12 IR rangers (metres), 16 switches.")
