// The kernel's receive timestamp of a datagram or CAN frame read with recvmsg() on a socket
// with SO_TIMESTAMP set: when it reached the socket, not when this process got to read it
// (candump's timestamps). Wall clock [s]; 0 when the kernel attached none.
#pragma once

#include <sys/socket.h>
#include <sys/time.h>

#include <cstring>

namespace hcl_drivers {
namespace transport {

inline double receiveTimestamp(msghdr& msg) {
  for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
    if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMP) {
      timeval tv{};
      std::memcpy(&tv, CMSG_DATA(c), sizeof(tv));
      return static_cast<double>(tv.tv_sec) + 1e-6 * static_cast<double>(tv.tv_usec);
    }
  }
  return 0.0;
}

}  // namespace transport
}  // namespace hcl_drivers
