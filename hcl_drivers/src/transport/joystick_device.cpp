#include "hcl_drivers/transport/joystick_device.h"

#include <fcntl.h>
#include <linux/joystick.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace hcl_drivers {
namespace transport {

JoystickDevice::JoystickDevice(std::string path) : path_(std::move(path)) {}

JoystickDevice::~JoystickDevice() { close(); }

bool JoystickDevice::open(std::string& error) {
  close();
  fd_ = ::open(path_.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) {
    error = "cannot open " + path_ + ": " + std::strerror(errno);
    return false;
  }
  struct stat st {};
  is_fifo_ = ::fstat(fd_, &st) == 0 && S_ISFIFO(st.st_mode);
  delivering_ = !is_fifo_;
  uint8_t n = 0;
  axes_ = ::ioctl(fd_, JSIOCGAXES, &n) == 0 ? n : 0;
  n = 0;
  buttons_ = ::ioctl(fd_, JSIOCGBUTTONS, &n) == 0 ? n : 0;
  char name[128] = {0};
  name_ = ::ioctl(fd_, JSIOCGNAME(sizeof(name) - 1), name) >= 0 ? std::string(name) : path_;
  return true;
}

void JoystickDevice::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  delivering_ = false;
}

bool JoystickDevice::readAvailable(std::vector<uint8_t>& out, std::string& error) {
  if (fd_ < 0) {
    error = path_ + " is not open";
    return false;
  }
  uint8_t buf[512];
  while (true) {
    pollfd p{fd_, POLLIN, 0};
    // A FIFO with no writer yet polls quiet (no POLLHUP until a writer came and went).
    if (::poll(&p, 1, 0) <= 0) return true;
    const ssize_t n = ::read(fd_, buf, sizeof(buf));
    if (n > 0) {
      out.insert(out.end(), buf, buf + n);
      delivering_ = true;
      continue;
    }
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) return true;
    error = n == 0 ? path_ + ": device hung up (unplugged)" : path_ + ": " + std::strerror(errno);
    close();
    return false;
  }
}

}  // namespace transport
}  // namespace hcl_drivers
