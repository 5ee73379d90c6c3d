// A serial line through termios: raw 8N1 at a configured baud rate, no flow control.
// The same code opens /dev/ttyS* / /dev/ttyUSB* on the robot and the emulator's pty in
// simulation. Reads wait with poll(); a vanished device (USB adapter unplugged, emulator
// gone) closes the port, and the owner reopens it.
#pragma once

#include <termios.h>

#include <cstdint>
#include <string>

namespace hcl_drivers {
namespace transport {

class SerialPort {
 public:
  SerialPort(std::string path, int baud);
  ~SerialPort();
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  // termios constant for a baud rate, 0 when unsupported (allowed: 1200..921600 standard rates).
  static speed_t baudConstant(int baud);
  static const char* allowedBauds();

  bool open(std::string& error);
  void close();
  bool isOpen() const { return fd_ >= 0; }
  // Waits up to timeout_s for bytes. Returns the count read (0: timeout), or -1 after an
  // error (the port is then closed; `error` says why).
  long read(uint8_t* buf, std::size_t n, double timeout_s, std::string& error);
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int baud_;
  int fd_ = -1;
};

}  // namespace transport
}  // namespace hcl_drivers
