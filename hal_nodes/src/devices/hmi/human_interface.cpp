// HumanInterface: the robot's few human controls behind one interface, whatever the hardware
// (2009: CAN HMI board with a 2x16 LCD and a keypad, start cord and colour switch on the
// servo board; Logion: MCP23016 buttons and LEDs). Publishes hal_nodes/HumanInput on ~input
// (/hal/hmi/input): start cord, `started` (the cord was pulled after being inserted: the
// match start, latched until the device restarts), the selected side and strategy, and key
// edges. Side and strategy are chosen before the start and frozen after it. The choice and
// the state are shown on the LCD or on LEDs; the brain may put text on the LCD's second
// line through ~text (std_msgs/String). Keys are reported as edges; the keys `next_strategy`
// and `toggle_side` (without a side switch) also change the choice.
//
// Parameters: read and described in configure() (the table: hal_nodes/PARAMETERS.md, make docs).
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
    params.describe("max_input_age", "[s] a board whose inputs are older makes the device unavailable");
    max_input_age_ = params.optionalDouble("max_input_age", 0.5);
    params.requirePositive("max_input_age", max_input_age_);
    params.describe("start_cord", "the start cord's switch (contact_input.h): closed = cord inserted");
    cord_ = ContactSpec::read(params, "start_cord");
    params.describe("sides", "the two sides/colours, e.g. [blue, yellow]");
    sides_ = params.optionalStringList("sides", {});
    if (sides_.size() != 2)
      throw robot_core::ParameterError("parameter " + params.qualified("sides") + " must list exactly 2 names");
    side_switch_.reset();
    params.describe("side_switch",
                    "switch (contact_input.h): open = sides[0], closed = sides[1]; none: the toggle_side key");
    if (params.has("side_switch")) side_switch_ = ContactSpec::read(params, "side_switch");
    params.describe("strategies", "the strategy names offered (at least one); the first is the default");
    strategies_ = params.optionalStringList("strategies", {});
    if (strategies_.empty())
      throw robot_core::ParameterError("parameter " + params.qualified("strategies") +
                                       " must list at least one strategy");
    keys_.clear();
    params.describe("keys", "switches by name (contact_input.h) reported as key edges");
    for (const auto& k : params.blockNames("keys")) keys_.push_back(Key{k, ContactSpec::read(params, "keys/" + k)});
    params.describe("display", "where the choice and the state are shown: lcd, leds or none");
    display_ = params.optionalString("display", "none");
    params.requireOneOf("display", display_, {"lcd", "leds", "none"});
    // the other display's settings, kept for when it is chosen again, are not unknown keys
    for (const char* other : {"lcd", "leds", "led_bits"})
      if (display_ != (std::string(other) == "led_bits" ? "leds" : other)) params.unused(other);
    if (display_ == "lcd") {
      params.describe("lcd", "the LCD topic out (std_msgs/String, lines separated by '\\n'), for display lcd");
      lcd_topic_ = params.requireString("lcd");
    }
    if (display_ == "leds") {
      params.describe("leds", "the LED output topic (std_msgs/UInt16 bits), for display leds");
      leds_topic_ = params.requireString("leds");
      const std::pair<const char*, const char*> bits[] = {
          {"armed", "output bit 0..15 lit while the cord is in before the start (display leds)"},
          {"started", "output bit 0..15 lit once the match started (display leds)"},
          {"side", "output bit 0..15 lit for sides[1] (display leds)"}};
      for (const auto& [n, meaning] : bits) {
        const std::string name = std::string("led_bits/") + n;
        params.describe(name, meaning);
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
