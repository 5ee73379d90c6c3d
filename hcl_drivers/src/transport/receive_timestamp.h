// The kernel's receive timestamp of what a socket receives (SO_TIMESTAMP, read with recvmsg()):
// when a datagram or CAN frame reached the socket, not when this process got to read it
// (candump's timestamps). Wall clock [s]; 0 when the kernel attached none.
#pragma once

#include <sys/socket.h>
#include <sys/time.h>
#include <sys/uio.h>

#include <cstring>

namespace hcl_drivers {
namespace transport {

// Asks the kernel to stamp what `fd` receives.
inline void enableReceiveTimestamps(int fd) {
  const int on = 1;
  ::setsockopt(fd, SOL_SOCKET, SO_TIMESTAMP, &on, sizeof(on));
}

// recv() (recvfrom() when `from` is given) that also returns the receive timestamp in
// `*received`. Same return value and errno as recvmsg().
inline ssize_t receiveStamped(int fd, void* buf, std::size_t len, int flags, double* received,
                              sockaddr* from = nullptr, socklen_t from_len = 0) {
  iovec iov{buf, len};
  alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timeval))];
  msghdr msg{};
  msg.msg_name = from;
  msg.msg_namelen = from ? from_len : 0;
  msg.msg_iov = &iov;
  msg.msg_iovlen = 1;
  msg.msg_control = control;
  msg.msg_controllen = sizeof(control);
  const ssize_t n = ::recvmsg(fd, &msg, flags);
  *received = 0.0;
  if (n < 0) return n;
  for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
    if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMP) {
      timeval tv{};
      std::memcpy(&tv, CMSG_DATA(c), sizeof(tv));
      *received = static_cast<double>(tv.tv_sec) + 1e-6 * static_cast<double>(tv.tv_usec);
    }
  }
  return n;
}

}  // namespace transport
}  // namespace hcl_drivers
