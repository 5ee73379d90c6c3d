// A USB joystick through the Linux joystick API (boards/js_event.h).
//
// service() (at ~rate) drains the device's js_events; the stick's state is published on
// ~joy as sensor_msgs/Joy at once when it changed and at least every 1/~publish_rate
// otherwise. Unplugged (ENODEV, or the sim FIFO's writer gone): the axes and buttons are
// published centred/released once (a vanished stick must not keep a button pressed), the
// board reports the error on /diagnostics and the device is reopened every ~reopen_period
// until it is back; the init events the kernel sends on open restore the true state.
//
// Parameters (besides rate/loop): read and described in configure() (the table:
// hcl_drivers/PARAMETERS.md, make docs).
// Topics: ~joy (sensor_msgs/Joy), ~state (hcl_drivers/JoystickState, latched, raw mirror).
#include <hcl_drivers/JoystickState.h>
#include <sensor_msgs/Joy.h>

#include <mutex>

#include <robot_core/priority_inheritance_mutex.h>
#include <chrono>
#include <thread>

#include "hcl_drivers/board_nodelet.h"
#include "hcl_drivers/boards/js_event.h"
#include "hcl_drivers/transport/joystick_device.h"

namespace hcl_drivers {

class Joystick : public Board {
 public:
  void configure(const robot_core::Params& p) override {
    p.describe("device", "the joystick device, /dev/input/js0, or the simulator's FIFO");
    device_path_ = p.requireString("device");
    p.describe("deadzone", "fraction of full travel around the centre read as 0 (the rest is rescaled to reach +-1)");
    deadzone_ = p.optionalDouble("deadzone", 0.05);
    p.requireInRange("deadzone", deadzone_, 0.0, 0.9);
    // The polling rate, for ~publish_rate: required and checked by the framework (BoardSettings)
    // before configure(); the doctor polls nothing and takes 10 Hz when absent.
    p.describe("rate", "[Hz] polling rate of the board");
    const double rate = p.optionalDouble("rate", 10.0);
    p.requirePositive("rate", rate);
    p.describe("publish_rate", "[Hz] repeat rate of ~joy when nothing changes (at most rate)");
    publish_rate_ = p.optionalDouble("publish_rate", std::min(10.0, rate));
    p.requireInRange("publish_rate", publish_rate_, 0.1, rate);
    p.describe("reopen_period", "[s] an unplugged joystick is reopened this often until it is back");
    reopen_period_ = p.optionalDouble("reopen_period", 0.5);
    p.requirePositive("reopen_period", reopen_period_);
    p.describe("frame_id", "frame_id of the Joy messages' header");
    frame_id_ = p.optionalString("frame_id", "");
    // the doctor's (check())
    p.describe("axes", "number of axes the hardware doctor expects the device to report; 0 = anything");
    want_axes_ = p.optionalInt("axes", 0);
    p.describe("buttons", "number of buttons the hardware doctor expects the device to report; 0 = anything");
    want_buttons_ = p.optionalInt("buttons", 0);
    p.describe("check_window", "[s] how long the hardware doctor waits for the init events a FIFO delivers");
    check_window_ = p.optionalDouble("check_window", 1.0);
    p.describe("required", "true: the robot is not ready for a match without this board; false: reported, not waited for");
    required_ = p.optionalBool("required", true);
  }

  void init(BoardContext& ctx) override {
    device_ = std::make_unique<transport::JoystickDevice>(device_path_);
    joy_pub_ = ctx.pnh.advertise<sensor_msgs::Joy>("joy", 10);
    state_pub_ = ctx.pnh.advertise<JoystickState>("state", 1, true);
  }

  // The doctor: the device opens and reports its axes and buttons (JSIOCGAXES/JSIOCGBUTTONS,
  // or the init events a FIFO delivers within ~check_window); compared with the
  // optional ~axes / ~buttons the robot's config expects.
  void check(BoardContext& /*ctx*/, CheckReport& report) override {
    transport::JoystickDevice device(device_path_);
    const int want_axes = want_axes_;
    const int want_buttons = want_buttons_;
    const double window = check_window_;
    std::string error;
    const bool required = required_;
    if (!device.open(error)) {
      const std::string hint = "is it plugged in (ls -l " + device.path() + ")? make install-robot gives it this name";
      if (required)
        report.fail("device", device.path(), error, hint);
      else
        report.warn("device", device.path(), error + " (optional board)", hint);
      return;
    }
    int axes = device.axes(), buttons = device.buttons();
    if (axes == 0 && buttons == 0) {  // a FIFO: count the init events
      js::Decoder decoder;
      std::vector<js::Event> events;
      std::vector<uint8_t> bytes;
      const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(window);
      while (std::chrono::steady_clock::now() < until && device.readAvailable(bytes, error)) {
        decoder.feed(bytes.data(), bytes.size(), events);
        bytes.clear();
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
      for (const auto& e : events) {
        if (e.type & js::kAxis) axes = std::max(axes, e.number + 1);
        if (e.type & js::kButton) buttons = std::max(buttons, e.number + 1);
      }
    }
    const std::string found = std::to_string(axes) + " axes, " + std::to_string(buttons) + " buttons" +
                              (device.name().empty() || device.name() == device.path() ? "" : " ('" + device.name() + "')");
    const std::string expected = (want_axes ? std::to_string(want_axes) : std::string("any")) + " axes, " +
                                 (want_buttons ? std::to_string(want_buttons) : std::string("any")) + " buttons";
    if ((want_axes && axes != want_axes) || (want_buttons && buttons != want_buttons))
      report.fail("controls", expected, found, "another joystick model than the config's: set ~axes/~buttons or plug in the right one");
    else
      report.ok("controls", expected, found);
  }

  bool service() override {
    const ros::Time now = ros::Time::now();
    std::string err;
    if (!device_->isOpen()) {
      if (!last_open_try_.isZero() && (now - last_open_try_).toSec() < reopen_period_) {
        fail(error_);
        return false;
      }
      last_open_try_ = now;
      if (!device_->open(err)) {
        error_ = err;
        fail(err);
        return false;
      }
      decoder_.reset();
      state_.resize(device_->axes(), device_->buttons());
      if (ever_connected_) {
        std::lock_guard lk(mutex_);
        ++reopens_;
      }
    }
    bytes_.clear();
    const bool alive = device_->readAvailable(bytes_, err);
    events_.clear();
    decoder_.feed(bytes_.data(), bytes_.size(), events_);
    bool changed = false;
    for (const auto& e : events_) {
      std::lock_guard lk(mutex_);
      ++event_count_;
      if (state_.apply(e))
        changed = true;
      else
        ++bad_events_;
    }
    if (!alive) {
      ROS_WARN("joystick %s: %s; axes centred, buttons released", device_->path().c_str(), err.c_str());
      error_ = err;
      state_.clear();
      connected_ = false;
      last_open_try_ = now;
      publish(now);
      fail(err);
      return false;
    }
    if (!device_->delivering()) {
      error_ = "waiting for " + device_->path() + " to deliver events";
      fail(error_);
      return false;
    }
    if (!connected_) changed = true;
    connected_ = ever_connected_ = true;
    if (changed || last_publish_.isZero() || (now - last_publish_).toSec() >= 1.0 / publish_rate_) publish(now);
    return true;
  }

  void halt() override {}  // an input device: nothing to make safe

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    std::lock_guard lk(mutex_);
    stat.add("device", device_->path());
    stat.add("connected", connected_ ? "yes" : "no");
    stat.add("reopens", reopens_);
    stat.add("events", event_count_);
    stat.add("bad events", bad_events_);
  }

 private:
  void publish(const ros::Time& now) {
    last_publish_ = now;
    sensor_msgs::Joy::Ptr j(new sensor_msgs::Joy);
    j->header.stamp = now;
    j->header.frame_id = frame_id_;
    for (int16_t a : state_.axes()) j->axes.push_back(static_cast<float>(js::applyDeadzone(a, deadzone_)));
    for (uint8_t b : state_.buttons()) j->buttons.push_back(b);
    joy_pub_.publish(j);
    JoystickState::Ptr s(new JoystickState);
    s->header.stamp = now;
    s->connected = connected_;
    s->device = device_->path();
    s->name = device_->name();
    s->axes = j->axes;
    s->buttons = j->buttons;
    std::lock_guard lk(mutex_);
    s->reconnects = reopens_;
    s->events = event_count_;
    s->bad_events = bad_events_;
    state_pub_.publish(s);
  }

  std::string device_path_;  // ~device
  int want_axes_ = 0, want_buttons_ = 0;
  double check_window_ = 1.0;
  bool required_ = true;
  std::unique_ptr<transport::JoystickDevice> device_;  // loop thread only
  js::Decoder decoder_;
  js::State state_;
  std::vector<uint8_t> bytes_;
  std::vector<js::Event> events_;
  double deadzone_ = 0.05, publish_rate_ = 10.0, reopen_period_ = 0.5;
  std::string frame_id_, error_;
  ros::Time last_open_try_, last_publish_;
  bool connected_ = false, ever_connected_ = false;
  ros::Publisher joy_pub_, state_pub_;

  robot_core::PriorityInheritanceMutex mutex_;  // counters: loop vs diagnostics
  uint32_t reopens_ = 0, event_count_ = 0, bad_events_ = 0;
};

}  // namespace hcl_drivers

HCL_EXPORT_BOARD(Joystick,
                 "Linux joystick (/dev/input/jsN, struct js_event): sensor_msgs/Joy with deadzone, survives replug.")
