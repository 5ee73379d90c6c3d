#include "robot_sim/firmware/channel_check.h"

#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>


namespace robot_sim {

namespace {

bool tcpPortTaken(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  // As the camera emulator binds: connections of a finished run (TIME_WAIT) do not hold the
  // port, a listening simulation does.
  const int one = 1;
  ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const bool taken = ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0 && errno == EADDRINUSE;
  ::close(fd);
  return taken;
}

// A unix socket someone listens on, or a link to a terminal that still exists: live. A FIFO is
// not judged (its reader may be this very robot's driver, started before the simulator).
std::string pathInUse(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return "";
  if (S_ISLNK(st.st_mode)) {
    struct stat target {};
    if (::stat(path.c_str(), &target) == 0 && S_ISCHR(target.st_mode))
      return path + " is the pty of a running simulation";
    return "";
  }
  if (S_ISSOCK(st.st_mode)) {
    // The emulated I2C bus (i2c_bus_server): a listener accepts, a leftover file refuses.
    const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::strncpy(addr.sun_path, path.c_str(), sizeof(addr.sun_path) - 1);
    const bool live = fd >= 0 && ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) == 0;
    if (fd >= 0) ::close(fd);
    if (live) return path + " is served by a running simulation";
  }
  return "";
}

std::string str(XmlRpc::XmlRpcValue& block, const char* key) {
  return block.hasMember(key) && block[key].getType() == XmlRpc::XmlRpcValue::TypeString
             ? static_cast<std::string>(block[key])
             : std::string();
}

}  // namespace

std::vector<std::string> channelsInUse(XmlRpc::XmlRpcValue& firmware) {
  std::vector<std::string> why;
  if (firmware.getType() != XmlRpc::XmlRpcValue::TypeStruct) return why;
  for (auto& entry : firmware) {
    XmlRpc::XmlRpcValue& block = entry.second;
    const std::string& name = entry.first;
    if (block.getType() != XmlRpc::XmlRpcValue::TypeStruct || !block.hasMember("type")) continue;
    if (block.hasMember("enabled") && block["enabled"].getType() == XmlRpc::XmlRpcValue::TypeBoolean &&
        !static_cast<bool>(block["enabled"]))
      continue;
    if (block.hasMember("port") && block["port"].getType() == XmlRpc::XmlRpcValue::TypeInt) {
      const int port = static_cast<int>(block["port"]);
      if (port > 0 && port < 65536 && tcpPortTaken(port))
        why.push_back(name + ": TCP port " + std::to_string(port) + " is taken");
    }
    for (const char* key : {"port", "device", "bus"}) {
      std::string path = str(block, key);
      if (path.rfind("sim://", 0) == 0) path = path.substr(6);
      if (path.empty() || path[0] != '/') continue;
      const std::string in_use = pathInUse(path);
      if (!in_use.empty()) why.push_back(name + ": " + in_use);
    }
  }
  return why;
}

}  // namespace robot_sim
