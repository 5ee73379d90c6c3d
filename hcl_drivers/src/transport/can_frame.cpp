#include "hcl_drivers/transport/can_frame.h"

#include <cstdio>

namespace hcl_drivers {
namespace transport {

bool CanFrame::operator==(const CanFrame& o) const {
  if (id != o.id || extended != o.extended || rtr != o.rtr || error != o.error || dlc != o.dlc) return false;
  if (rtr) return true;  // a remote frame carries no data
  for (int i = 0; i < dlc && i < 8; ++i)
    if (data[i] != o.data[i]) return false;
  return true;
}

std::string toString(const CanFrame& f) {
  char buf[64];
  int n = 0;
  if (f.error)
    n = std::snprintf(buf, sizeof(buf), "ERR:%08X#", f.id);
  else if (f.extended)
    n = std::snprintf(buf, sizeof(buf), "%08X#", f.id);
  else
    n = std::snprintf(buf, sizeof(buf), "%03X#", f.id);
  std::string s(buf, static_cast<std::size_t>(n));
  if (f.rtr) return s + "R" + std::to_string(f.dlc);
  for (int i = 0; i < f.dlc && i < 8; ++i) {
    std::snprintf(buf, sizeof(buf), "%02X", f.data[i]);
    s += buf;
  }
  return s;
}

}  // namespace transport
}  // namespace hcl_drivers
