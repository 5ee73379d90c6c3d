// HmiBoard: the 2009 robot's human interface board: a 2x16 character LCD and a 4x4 keypad
// (protocol: hmi_board_protocol.h).
//
// Parameters (besides the CANopen ones in canopen_board.h): read and described in readParams()
// (the table: hcl_drivers/PARAMETERS.md, make docs).
// Topics:
//   in   ~lcd      std_msgs/String: the whole display, lines separated by '\n' (2 lines of 16
//                  printable ASCII characters; longer lines are cut, others become '?').
//                  Only the 6-character chunks that changed are sent, at most 4 frames per poll;
//                  everything is sent again after the board resets.
//   out  ~inputs   hcl_drivers/DigitalInputs (keys held), latched
//   out  ~state    hcl_drivers/HmiBoardState, latched
#include <hcl_drivers/DigitalInputs.h>
#include <hcl_drivers/HmiBoardState.h>
#include <std_msgs/String.h>

#include "canopen_board.h"
#include "hcl_drivers/board_nodelet.h"
#include "hmi_board_protocol.h"

namespace hcl_drivers {

using robot_core::ParameterError;

class HmiBoard : public CanopenBoard {
 protected:
  void readParams(const robot_core::Params& p) override {
    p.describe("keys", "names of keys 0..15 in bit order (up to 16)");
    key_names_ = p.optionalStringList("keys", {"0", "1", "2", "3", "4", "5", "6", "7", "8", "9", "A", "B", "C", "D", "*", "#"});
    if (key_names_.size() > 16) throw ParameterError("parameter " + p.qualified("keys") + ": at most 16 key names");
    const uint32_t n = static_cast<uint32_t>(nodeId());
    lcd_cob_ = cobIdParam(p, "lcd_cob_id", canopen::kRpdo1 + n, "COB-ID of the RPDO with the LCD characters");
    keys_cob_ = cobIdParam(p, "keys_cob_id", canopen::kTpdo1 + n, "COB-ID of the TPDO with the keys held");
  }

  void setup(BoardContext& ctx) override {
    for (auto& l : wanted_) l = hmi_board::lcdLine("");
    shown_ = {std::string(hmi_board::kColumns, '\x01'), std::string(hmi_board::kColumns, '\x01')};  // unknown

    node().onFrame(keys_cob_, [this](const CanFrame& f) {
      const auto k = hmi_board::decodeKeys(f);
      if (!k) return false;
      std::lock_guard lk(mutex_);
      keys_ = *k;
      got_keys_ = true;
      return true;
    });
    state_pub_ = ctx.pnh.advertise<HmiBoardState>("state", 1, true);
    inputs_pub_ = ctx.pnh.advertise<DigitalInputs>("inputs", 1, true);
    lcd_sub_ = subscribeCommand<std_msgs::String>(ctx, "lcd", [this](const std_msgs::String::ConstPtr& m) {
      if (!acceptCommand("LCD")) return;
      std::lock_guard lk(mutex_);
      std::size_t start = 0;
      for (int line = 0; line < hmi_board::kLines; ++line) {
        const std::size_t nl = m->data.find('\n', start);
        const std::string text = start > m->data.size() ? "" : m->data.substr(start, nl == std::string::npos ? std::string::npos : nl - start);
        wanted_[line] = hmi_board::lcdLine(text);
        start = nl == std::string::npos ? m->data.size() + 1 : nl + 1;
      }
    });
  }

  void configureNode() override {
    std::lock_guard lk(mutex_);  // after a reset the LCD is blank: send everything
    for (auto& s : shown_) s.assign(hmi_board::kColumns, '\x01');
  }

  bool exchange() override {
    // LCD: changed chunks first (bounded, so a full rewrite takes a few polls, not one long one).
    std::vector<CanFrame> frames;
    {
      std::lock_guard lk(mutex_);
      for (int line = 0; line < hmi_board::kLines && frames.size() < 4; ++line)
        for (int col = 0; col < hmi_board::kColumns && frames.size() < 4; col += hmi_board::kCharsPerFrame) {
          const std::string want = wanted_[line].substr(col, hmi_board::kCharsPerFrame);
          if (shown_[line].substr(col, hmi_board::kCharsPerFrame) == want) continue;
          frames.push_back(hmi_board::encodeLcd(lcd_cob_, static_cast<uint8_t>(line), static_cast<uint8_t>(col), want));
          shown_[line].replace(col, want.size(), want);
        }
      got_keys_ = false;
    }
    for (const auto& f : frames)
      if (!node().sendRaw(f)) {
        fail("sending LCD text: " + node().lastError());
        configureNode();  // unknown what arrived: send it all again
        return false;
      }
    const bool answered = requestPdos({{keys_cob_, 4}},
                                      [this] {
                                        std::lock_guard lk(mutex_);
                                        return got_keys_;
                                      },
                                      "HMI board");
    if (!answered) return false;
    publishState();
    return true;
  }

  void stopActuators() override {}  // an LCD and a keypad: nothing moves

  void publishState() override {
    HmiBoardState::Ptr s(new HmiBoardState);
    s->header.stamp = ros::Time::now();
    fillStatus(s->node);
    std::lock_guard lk(mutex_);
    s->lcd_lines = {wanted_[0], wanted_[1]};
    s->keys = keys_.held;
    s->last_key = keys_.last_key;
    s->key_presses = keys_.presses;
    if (s->node.answering) {
      DigitalInputs::Ptr in(new DigitalInputs);
      in->header.stamp = s->header.stamp;
      in->bits = keys_.held;
      in->names = key_names_;
      inputs_pub_.publish(in);
    }
    state_pub_.publish(s);
  }

 private:
  std::vector<std::string> key_names_;
  uint32_t lcd_cob_ = 0, keys_cob_ = 0;
  ros::Publisher state_pub_, inputs_pub_;
  ros::Subscriber lcd_sub_;

  robot_core::PriorityInheritanceMutex mutex_;
  std::array<std::string, hmi_board::kLines> wanted_, shown_;
  hmi_board::Keys keys_;
  bool got_keys_ = false;
};

}  // namespace hcl_drivers

HCL_EXPORT_BOARD(HmiBoard, "CAN human interface board: 2x16 character LCD, 4x4 keypad.")
