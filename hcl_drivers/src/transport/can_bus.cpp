#include "hcl_drivers/transport/can_bus.h"

#include <map>
#include <stdexcept>

#include "hcl_drivers/transport/endpoint.h"
#include "hcl_drivers/transport/socketcan_bus.h"
#include "hcl_drivers/transport/udp_can_bus.h"

namespace hcl_drivers {
namespace transport {

std::shared_ptr<CanBus> openCanBus(const std::string& url) {
  static std::mutex mutex;
  static std::map<std::string, std::weak_ptr<CanBus>> buses;
  std::lock_guard<std::mutex> lk(mutex);
  if (auto existing = buses[url].lock()) return existing;
  const Endpoint ep = parseEndpoint(url);
  std::shared_ptr<CanBus> bus;
  if (ep.scheme == "socketcan") {
    bus = std::make_shared<SocketCanBus>(ep.host);
  } else if (ep.scheme == "udp") {
    bus = std::make_shared<UdpCanBus>(url, ep.host, ep.port);
  } else {
    throw std::invalid_argument("bad CAN bus '" + url + "': expected socketcan://IFACE or udp://127.0.0.1:PORT");
  }
  buses[url] = bus;
  return bus;
}

}  // namespace transport
}  // namespace hcl_drivers
