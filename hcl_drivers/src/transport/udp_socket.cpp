#include "hcl_drivers/transport/udp_socket.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <system_error>

namespace hcl_drivers {
namespace transport {

UdpSocket::UdpSocket(const std::string& host, uint16_t port) {
  fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw std::system_error(errno, std::generic_category(), "socket(AF_INET, SOCK_DGRAM)");
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  if (::inet_pton(AF_INET, host.c_str(), &addr.sin_addr) != 1) {
    ::close(fd_);
    throw std::system_error(EINVAL, std::generic_category(), "not an IPv4 address: " + host);
  }
  if (::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
    const int err = errno;
    ::close(fd_);
    throw std::system_error(err, std::generic_category(), "connect to " + host + ":" + std::to_string(port));
  }
}

UdpSocket::~UdpSocket() {
  if (fd_ >= 0) ::close(fd_);
}

bool UdpSocket::send(const std::vector<uint8_t>& datagram) {
  const ssize_t n = ::send(fd_, datagram.data(), datagram.size(), 0);
  if (n != static_cast<ssize_t>(datagram.size())) {
    last_error_ = std::string("send: ") + std::strerror(errno);
    return false;
  }
  return true;
}

bool UdpSocket::receive(std::vector<uint8_t>& datagram, double timeout_s) {
  pollfd p{fd_, POLLIN, 0};
  const int ms = static_cast<int>(std::ceil(timeout_s * 1e3));
  const int r = ::poll(&p, 1, ms);
  if (r == 0) {
    last_error_ = "timeout after " + std::to_string(ms) + " ms";
    return false;
  }
  if (r < 0) {
    last_error_ = std::string("poll: ") + std::strerror(errno);
    return false;
  }
  datagram.resize(2048);
  const ssize_t n = ::recv(fd_, datagram.data(), datagram.size(), 0);
  if (n < 0) {
    // ECONNREFUSED: the ICMP "port unreachable" of a previous send: nobody listens.
    last_error_ = std::string("recv: ") + std::strerror(errno);
    datagram.clear();
    return false;
  }
  datagram.resize(static_cast<std::size_t>(n));
  return true;
}

void UdpSocket::drain() {
  uint8_t buf[2048];
  while (::recv(fd_, buf, sizeof(buf), MSG_DONTWAIT) >= 0) {
  }
}

}  // namespace transport
}  // namespace hcl_drivers
