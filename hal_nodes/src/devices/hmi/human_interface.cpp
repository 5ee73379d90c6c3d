// HumanInterface: the robot's few human controls behind one interface, whatever the hardware
// (2009: CAN HMI board with a 2x16 LCD and a keypad, start cord and colour switch on the
// servo board; Logion: MCP23016 buttons and LEDs). Publishes hal_nodes/HumanInput on ~input
// (/hal/hmi/input): start cord, `started` (the cord was pulled after being inserted: the
// match start, latched until the device restarts), the selected side and strategy, and key
// edges. Side and strategy are chosen before the start and frozen after it. The choice and
// the state are shown on the LCD or on LEDs; the brain may put text on the LCD's second
// line through ~text (std_msgs/String).
//
// Parameters (besides ~rate):
//   ~start_cord   contact (contact_input.h): closed = cord inserted (required)
//   ~sides        the two sides/colours, e.g. [blue, yellow] (required, 2 names)
//   ~side_switch  contact: open = sides[0], closed = sides[1] (optional; else the toggle_side key)
//   ~strategies   the strategy names offered (required, >= 1); the first is the default
//   ~keys/<name>  contacts reported as key edges; `next_strategy` and `toggle_side` also act
//   ~display      lcd | leds | none (default none)
//   ~lcd          the LCD topic (std_msgs/String, lines separated by '\n'), for display: lcd
//   ~leds         the LED output topic (std_msgs/UInt16 bits), for display: leds
//   ~led_bits/{armed, started, side}   output bit numbers 0..15 (display: leds)
//   ~max_input_age [s] (default 0.5)
#include <hal_nodes/HumanInput.h>
#include <std_msgs/String.h>
#include <std_msgs/UInt16.h>

#include <map>

#include "hal_nodes/device_nodelet.h"
#include <robot_core/params.h>
#include "hal_nodes/devices/contact_input.h"

namespace hal_nodes {

class HumanInterface : public Device {
 public:
  void configure(const robot_core::Params& params) override {
    max_input_age_ = params.optionalDouble("max_input_age", 0.5);
    params.requirePositive("max_input_age", max_input_age_);
    cord_ = ContactSpec::read(params, "start_cord");
    sides_ = params.optionalStringList("sides", {});
    if (sides_.size() != 2)
      throw robot_core::ParameterError("parameter " + params.qualified("sides") + " must list exactly 2 names");
    side_switch_.reset();
    if (params.has("side_switch")) side_switch_ = ContactSpec::read(params, "side_switch");
    strategies_ = params.optionalStringList("strategies", {});
    if (strategies_.empty())
      throw robot_core::ParameterError("parameter " + params.qualified("strategies") +
                                       " must list at least one strategy");
    keys_.clear();
    for (const auto& k : params.blockNames("keys")) keys_.push_back(Key{k, ContactSpec::read(params, "keys/" + k)});
    display_ = params.optionalString("display", "none");
    params.requireOneOf("display", display_, {"lcd", "leds", "none"});
    // the other display's settings, kept for when it is chosen again, are not unknown keys
    for (const char* other : {"lcd", "leds", "led_bits"})
      if (display_ != (std::string(other) == "led_bits" ? "leds" : other)) params.unused(other);
    if (display_ == "lcd") lcd_topic_ = params.requireString("lcd");
    if (display_ == "leds") {
      leds_topic_ = params.requireString("leds");
      for (const char* n : {"armed", "started", "side"}) {
        const std::string name = std::string("led_bits/") + n;
        const int b = params.requireInt(name);
        params.requireInRange(name, b, 0, 15);
        led_bits_[n] = b;
      }
    }
  }

  void init(DeviceContext& ctx) override {
    if (display_ == "lcd") lcd_pub_ = ctx.nh.advertise<std_msgs::String>(lcd_topic_, 1);
    if (display_ == "leds") leds_pub_ = ctx.nh.advertise<std_msgs::UInt16>(leds_topic_, 1);
    auto topicInput = [&](const std::string& topic) {
      if (!inputs_.count(topic)) inputs_[topic] = addInput<hcl_drivers::DigitalInputs>(ctx.nh, topic, topic);
    };
    topicInput(cord_.topic);
    if (side_switch_) topicInput(side_switch_->topic);
    for (const auto& k : keys_) topicInput(k.spec.topic);
    text_ = addInput<std_msgs::String>(ctx.pnh, "text", "text");
    pub_ = ctx.pnh.advertise<HumanInput>("input", 5);
  }

  void refresh() override {
    HumanInput out;
    out.header.stamp = ros::Time::now();
    std::string missing;
    auto read = [&](const ContactSpec& c) -> std::optional<bool> {
      const auto m = inputs_[c.topic]->fresh(max_input_age_);
      const auto v = m ? c.closed(*m) : std::nullopt;
      if (!v) missing += (missing.empty() ? "" : ", ") + c.topic + (c.input.empty() ? "" : " (" + c.input + ")");
      return v;
    };
    const auto cord = read(cord_);
    if (cord) {
      if (*cord) armed_ = true;
      else if (armed_ && !started_) {
        started_ = true;
        ROS_INFO("human interface: start cord pulled, the match starts");
      }
      cord_in_ = *cord;
    }
    if (side_switch_ && !started_) {
      if (const auto s = read(*side_switch_)) side_ = *s ? 1 : 0;
    }
    for (auto& k : keys_) {
      const auto v = read(k.spec);
      if (!v) continue;
      if (*v && !k.held && k.known) {
        out.pressed.push_back(k.name);
        if (!started_ && k.name == "next_strategy") strategy_ = (strategy_ + 1) % strategies_.size();
        if (!started_ && k.name == "toggle_side" && !side_switch_) side_ = 1 - side_;
      }
      k.held = *v;
      k.known = true;
    }
    out.cord_inserted = cord_in_;
    out.started = started_;
    out.side = sides_[side_];
    out.strategy = strategies_[strategy_];
    if (missing.empty()) setAvailable();
    else setUnavailable("no fresh input from " + missing);
    pub_.publish(out);
    show(out);
  }

 private:
  struct Key {
    std::string name;
    ContactSpec spec;
    bool held = false, known = false;
  };

  void show(const HumanInput& s) {
    if (display_ == "lcd") {
      // "ready" is the brain's word (its text input, while it waits for the start): the cord
      // alone does not make the robot ready.
      std::string line2 = s.started ? "GO!" : (s.cord_inserted ? "cord in" : "insert the cord");
      if (const auto t = text_->fresh(2.0)) line2 = t->data;
      std_msgs::String m;
      m.data = (s.side + " " + s.strategy).substr(0, 16) + "\n" + line2.substr(0, 16);
      const ros::Time now = ros::Time::now();
      if (m.data != last_lcd_ || (now - last_lcd_time_).toSec() > 2.0) {  // on change, and now and then
        lcd_pub_.publish(m);
        last_lcd_ = m.data;
        last_lcd_time_ = now;
      }
    } else if (display_ == "leds") {
      std_msgs::UInt16 m;
      if (s.cord_inserted && !s.started) m.data |= 1u << led_bits_["armed"];
      if (s.started) m.data |= 1u << led_bits_["started"];
      if (side_ == 1) m.data |= 1u << led_bits_["side"];
      leds_pub_.publish(m);
    }
  }

  ContactSpec cord_;
  std::optional<ContactSpec> side_switch_;
  std::vector<Key> keys_;
  std::vector<std::string> sides_, strategies_;
  std::map<std::string, std::shared_ptr<LatestValue<hcl_drivers::DigitalInputs>>> inputs_;
  std::shared_ptr<LatestValue<std_msgs::String>> text_;
  std::map<std::string, int> led_bits_;
  ros::Publisher pub_, lcd_pub_, leds_pub_;
  std::string display_, last_lcd_, lcd_topic_, leds_topic_;
  ros::Time last_lcd_time_;
  double max_input_age_ = 0.5;
  std::size_t side_ = 0, strategy_ = 0;
  bool armed_ = false, started_ = false, cord_in_ = false;
};

}  // namespace hal_nodes

HAL_EXPORT_DEVICE(HumanInterface, HumanInterface,
                  "Human interface: start cord, side and strategy choice, keys; shown on an LCD or LEDs.")
