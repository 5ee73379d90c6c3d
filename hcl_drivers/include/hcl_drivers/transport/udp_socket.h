// A connected UDP socket on loopback: the simulation channel for boards whose emulator
// answers datagrams (the skeleton's example board, CAN over UDP).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace hcl_drivers {
namespace transport {

class UdpSocket {
 public:
  // Connects to host:port from an ephemeral local port. Throws std::system_error.
  UdpSocket(const std::string& host, uint16_t port);
  ~UdpSocket();
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;

  // Sends one datagram. Returns false (errno kept in lastError()) if the kernel refused it.
  bool send(const std::vector<uint8_t>& datagram);
  // Waits up to timeout_s for one datagram. Returns false on timeout or error (see lastError()).
  bool receive(std::vector<uint8_t>& datagram, double timeout_s);
  // Drops any datagrams already queued (late answers to earlier requests).
  void drain();

  const std::string& lastError() const { return last_error_; }
  int fd() const { return fd_; }

 private:
  int fd_ = -1;
  std::string last_error_;
};

}  // namespace transport
}  // namespace hcl_drivers
