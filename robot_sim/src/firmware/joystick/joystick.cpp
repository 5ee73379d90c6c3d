// Emulator of a USB joystick: a FIFO at ~device that the driver opens like /dev/input/jsN,
// carrying struct js_event records (8 bytes, host order: u32 time ms, s16 value, u8 type
// 0x01 button / 0x02 axis (| 0x80 init), u8 number). Like the kernel, it sends one init
// event per button and per axis each time a reader connects. Written from linux/joystick.h,
// not from the driver's decoder.
//
// Parameters: robot_sim/PARAMETERS.md (Joystick).
// Script it (tests): /sim/<name>/axes (std_msgs/Int16MultiArray, raw axis values),
// /sim/<name>/buttons (std_msgs/UInt8MultiArray, 0/1), service /sim/<name>/plugged
// (std_srvs/SetBool: false unplugs: the writer closes and the FIFO disappears; true plugs back).
// Faults: "board_silent" = unplugged while active.
#include <fcntl.h>
#include <poll.h>
#include <linux/joystick.h>
#include <std_msgs/Int16MultiArray.h>
#include <std_msgs/UInt8MultiArray.h>
#include <std_srvs/SetBool.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <chrono>
#include <cstring>
#include <mutex>
#include <thread>

#include "robot_sim/firmware/firmware_registry.h"
#include <robot_core/realtime.h>

namespace robot_sim {

class JoystickFirmware : public Firmware {
 public:
  ~JoystickFirmware() override { stop(); }

  void configure(const robot_core::Params& params) override {
    params.describe("device", "the FIFO to create, an absolute path: the driver's device in simulation");
    device_ = params.requireString("device");
    if (device_.empty() || device_[0] != '/') params.check("device", "must be an absolute path for the FIFO");
    params.describe("axes", "how many axes the joystick has");
    const int axes = params.optionalInt("axes", 6);
    params.requireInRange("axes", axes, 0, 64);
    params.describe("buttons", "how many buttons it has");
    const int buttons = params.optionalInt("buttons", 12);
    params.requireInRange("buttons", buttons, 0, 128);
    axes_.assign(axes, 0);
    buttons_.assign(buttons, 0);
  }

  // The FIFO is made (and removed by stop()) only here: a checker that only configured an
  // emulator never touches the running simulation's device.
  void start(FirmwareContext& ctx) override {
    path_ = device_;
    for (std::size_t i = 1; i < path_.size(); ++i)
      if (path_[i] == '/') ::mkdir(path_.substr(0, i).c_str(), 0777);
    // A write to a FIFO whose reader just left must fail with EPIPE, not kill the simulator.
    ::signal(SIGPIPE, SIG_IGN);
    makeFifo();
    boot_ = std::chrono::steady_clock::now();
    const std::string base = "/sim/" + ctx.name + "/";
    axes_sub_ = ctx.nh.subscribe(base + "axes", 10, &JoystickFirmware::onAxes, this);
    buttons_sub_ = ctx.nh.subscribe(base + "buttons", 10, &JoystickFirmware::onButtons, this);
    plug_srv_ = ctx.nh.advertiseService(base + "plugged", &JoystickFirmware::onPlug, this);
    running_ = true;
    thread_ = std::thread([this] { run(); });
  }

  void stop() override {
    running_ = false;
    if (thread_.joinable()) thread_.join();
    closeWriter();
    if (!path_.empty()) ::unlink(path_.c_str());
  }

  bool applyFault(const std::string& kind, bool active) override {
    if (kind != "board_silent") return false;
    setSilent(active);
    plugged_ = !active;
    return true;
  }

 private:
  void makeFifo() {
    ::unlink(path_.c_str());
    if (::mkfifo(path_.c_str(), 0666) != 0)
      throw std::runtime_error("cannot create FIFO " + path_ + ": " + std::strerror(errno));
  }

  uint32_t nowMs() const {
    return static_cast<uint32_t>(
        std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - boot_).count());
  }

  // Called with mutex_ held.
  bool sendEvent(int16_t value, uint8_t type, uint8_t number) {
    if (fd_ < 0) return true;
    js_event e{};
    e.time = nowMs();
    e.value = value;
    e.type = type;
    e.number = number;
    if (::write(fd_, &e, sizeof(e)) == static_cast<ssize_t>(sizeof(e))) return true;
    closeWriterLocked();  // EPIPE: the reader went away; wait for the next one
    return false;
  }

  void onAxes(const std_msgs::Int16MultiArray::ConstPtr& m) {
    std::lock_guard<std::mutex> lk(mutex_);
    for (std::size_t i = 0; i < m->data.size() && i < axes_.size(); ++i) {
      if (axes_[i] == m->data[i]) continue;
      axes_[i] = m->data[i];
      sendEvent(axes_[i], JS_EVENT_AXIS, static_cast<uint8_t>(i));
    }
  }

  void onButtons(const std_msgs::UInt8MultiArray::ConstPtr& m) {
    std::lock_guard<std::mutex> lk(mutex_);
    for (std::size_t i = 0; i < m->data.size() && i < buttons_.size(); ++i) {
      const int16_t v = m->data[i] ? 1 : 0;
      if (buttons_[i] == v) continue;
      buttons_[i] = v;
      sendEvent(v, JS_EVENT_BUTTON, static_cast<uint8_t>(i));
    }
  }

  bool onPlug(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res) {
    plugged_ = req.data;
    res.success = true;
    res.message = req.data ? "plugged" : "unplugged";
    return true;
  }

  void closeWriterLocked() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }
  void closeWriter() {
    std::lock_guard<std::mutex> lk(mutex_);
    closeWriterLocked();
  }

  // Connects to each new reader (the kernel's open), sends the init events; follows plug state.
  void run() {
    robot_core::enterRealtime("the joystick emulator");
    bool fifo_present = true;
    while (running_) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      if (!plugged_) {
        if (fifo_present) {
          closeWriter();
          ::unlink(path_.c_str());  // like /dev/input/js0 vanishing
          fifo_present = false;
        }
        continue;
      }
      if (!fifo_present) {
        try {
          makeFifo();
        } catch (const std::exception& e) {
          ROS_ERROR_THROTTLE(5.0, "%s", e.what());
          continue;
        }
        fifo_present = true;
      }
      std::lock_guard<std::mutex> lk(mutex_);
      if (fd_ >= 0) {
        // The reader gone (a driver that died or closed the device): POLLERR on the write end.
        // Without this the next reader, a restarted driver, would wait for the init events the
        // kernel sends on each open, since nothing fails before the next write.
        pollfd p{fd_, POLLOUT, 0};
        if (::poll(&p, 1, 0) > 0 && (p.revents & POLLERR)) closeWriterLocked();
        continue;
      }
      fd_ = ::open(path_.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);  // ENXIO: no reader yet
      if (fd_ < 0) continue;
      for (std::size_t i = 0; i < buttons_.size() && fd_ >= 0; ++i)
        sendEvent(buttons_[i], JS_EVENT_BUTTON | JS_EVENT_INIT, static_cast<uint8_t>(i));
      for (std::size_t i = 0; i < axes_.size() && fd_ >= 0; ++i)
        sendEvent(axes_[i], JS_EVENT_AXIS | JS_EVENT_INIT, static_cast<uint8_t>(i));
    }
  }

  std::string path_;
  std::chrono::steady_clock::time_point boot_;
  std::mutex mutex_;  // state and writer fd: subscriber callbacks vs the connect thread
  std::vector<int16_t> axes_, buttons_;
  int fd_ = -1;
  std::string device_;  // configured; path_ once started
  std::atomic<bool> running_{false}, plugged_{true};
  std::thread thread_;
  ros::Subscriber axes_sub_, buttons_sub_;
  ros::ServiceServer plug_srv_;
};

ROBOT_SIM_REGISTER_FIRMWARE("Joystick", JoystickFirmware);

}  // namespace robot_sim
