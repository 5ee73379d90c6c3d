// A Linux joystick device (/dev/input/jsN) or anything else that delivers struct js_event
// records (the simulator's FIFO). Non-blocking: the owner polls it from its loop.
// "Connected" means events can arrive: a js device is connected once open; a FIFO once its
// writer delivered bytes. A hang-up (ENODEV: unplugged; EOF: FIFO writer gone) closes it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace hcl_drivers {
namespace transport {

class JoystickDevice {
 public:
  explicit JoystickDevice(std::string path);
  ~JoystickDevice();
  JoystickDevice(const JoystickDevice&) = delete;
  JoystickDevice& operator=(const JoystickDevice&) = delete;

  bool open(std::string& error);
  void close();
  bool isOpen() const { return fd_ >= 0; }
  bool delivering() const { return delivering_; }
  // From the JSIOCG* ioctls; 0 / the path when the device has none (a FIFO).
  int axes() const { return axes_; }
  int buttons() const { return buttons_; }
  const std::string& name() const { return name_; }
  const std::string& path() const { return path_; }

  // Appends whatever bytes are ready (no waiting). Returns false after a hang-up or error
  // (the device is then closed and `error` says why).
  bool readAvailable(std::vector<uint8_t>& out, std::string& error);

 private:
  std::string path_;
  int fd_ = -1;
  bool is_fifo_ = false;
  bool delivering_ = false;
  int axes_ = 0, buttons_ = 0;
  std::string name_;
};

}  // namespace transport
}  // namespace hcl_drivers
