// Where a bus is: parsed from the URL-like per-bus parameter, e.g.
//   udp://127.0.0.1:27100   socketcan://can0   /dev/i2c-1   sim:///run/robot_sim/i2c-1
#pragma once

#include <cstdint>
#include <string>

namespace hcl_drivers {
namespace transport {

struct Endpoint {
  std::string scheme;  // "udp", "socketcan", "sim", "file" (a plain path)
  std::string host;    // udp: address; socketcan: interface name
  uint16_t port = 0;   // udp only
  std::string path;    // sim/file: filesystem path
};

// Throws std::invalid_argument with a message naming the accepted forms.
Endpoint parseEndpoint(const std::string& url);

}  // namespace transport
}  // namespace hcl_drivers
