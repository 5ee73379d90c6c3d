#include "hcl_drivers/transport/serial_port.h"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace hcl_drivers {
namespace transport {

SerialPort::SerialPort(std::string path, int baud) : path_(std::move(path)), baud_(baud) {}

SerialPort::~SerialPort() { close(); }

speed_t SerialPort::baudConstant(int baud) {
  switch (baud) {
    case 1200: return B1200;
    case 2400: return B2400;
    case 4800: return B4800;
    case 9600: return B9600;
    case 19200: return B19200;
    case 38400: return B38400;
    case 57600: return B57600;
    case 115200: return B115200;
    case 230400: return B230400;
    case 460800: return B460800;
    case 921600: return B921600;
    default: return 0;
  }
}

const char* SerialPort::allowedBauds() { return "1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200, 230400, 460800, 921600"; }

bool SerialPort::open(std::string& error) {
  close();
  fd_ = ::open(path_.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) {
    error = "cannot open " + path_ + ": " + std::strerror(errno);
    return false;
  }
  termios tio{};
  if (::tcgetattr(fd_, &tio) != 0) {
    error = path_ + " is not a serial line: " + std::strerror(errno);
    close();
    return false;
  }
  ::cfmakeraw(&tio);  // 8N1, no echo, no CR/LF translation, no signals
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~CRTSCTS;
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  const speed_t speed = baudConstant(baud_);
  ::cfsetispeed(&tio, speed);
  ::cfsetospeed(&tio, speed);
  if (::tcsetattr(fd_, TCSANOW, &tio) != 0) {
    error = "cannot configure " + path_ + ": " + std::strerror(errno);
    close();
    return false;
  }
  ::tcflush(fd_, TCIFLUSH);  // bytes from before we were listening are stale
  return true;
}

void SerialPort::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

long SerialPort::read(uint8_t* buf, std::size_t n, double timeout_s, std::string& error) {
  if (fd_ < 0) {
    error = path_ + " is not open";
    return -1;
  }
  pollfd p{fd_, POLLIN, 0};
  const int r = ::poll(&p, 1, static_cast<int>(timeout_s * 1000.0));
  if (r == 0) return 0;
  if (r < 0) {
    if (errno == EINTR) return 0;
    error = std::string("poll: ") + std::strerror(errno);
    close();
    return -1;
  }
  const ssize_t got = ::read(fd_, buf, n);
  if (got > 0) return got;
  if (got < 0 && (errno == EAGAIN || errno == EINTR)) return 0;
  // POLLHUP/EIO or 0 bytes after POLLIN: the device went away (pty master closed, USB unplugged).
  error = got == 0 || (p.revents & POLLHUP) ? path_ + " hung up" : path_ + ": " + std::strerror(errno);
  close();
  return -1;
}

}  // namespace transport
}  // namespace hcl_drivers
