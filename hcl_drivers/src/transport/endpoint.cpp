#include "hcl_drivers/transport/endpoint.h"

#include <stdexcept>

namespace hcl_drivers {
namespace transport {

namespace {
const char* kForms = "expected udp://HOST:PORT, socketcan://IFACE, sim:///PATH or /dev/PATH";
}

Endpoint parseEndpoint(const std::string& url) {
  Endpoint e;
  const auto sep = url.find("://");
  if (sep == std::string::npos) {
    if (url.empty() || url[0] != '/') throw std::invalid_argument("bad endpoint '" + url + "': " + kForms);
    e.scheme = "file";
    e.path = url;
    return e;
  }
  e.scheme = url.substr(0, sep);
  const std::string rest = url.substr(sep + 3);
  if (e.scheme == "udp") {
    const auto colon = rest.rfind(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 >= rest.size())
      throw std::invalid_argument("bad endpoint '" + url + "': " + kForms);
    e.host = rest.substr(0, colon);
    std::size_t used = 0;
    long port = -1;
    try {
      port = std::stol(rest.substr(colon + 1), &used);
    } catch (const std::exception&) {
    }
    if (port <= 0 || port > 65535 || used != rest.size() - colon - 1)
      throw std::invalid_argument("bad port in endpoint '" + url + "': must be 1..65535");
    e.port = static_cast<uint16_t>(port);
  } else if (e.scheme == "socketcan") {
    if (rest.empty() || rest.find('/') != std::string::npos)
      throw std::invalid_argument("bad endpoint '" + url + "': " + kForms);
    e.host = rest;
  } else if (e.scheme == "sim") {
    if (rest.empty() || rest[0] != '/') throw std::invalid_argument("bad endpoint '" + url + "': " + kForms);
    e.path = rest;
  } else {
    throw std::invalid_argument("unknown scheme in endpoint '" + url + "': " + kForms);
  }
  return e;
}

}  // namespace transport
}  // namespace hcl_drivers
