// libFuzzer target: the CAN-over-UDP datagram decoder (udp_can_datagram.h wire format) and the error
// frame decoder behind it. A decoded frame must re-encode to the same datagram.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "hcl_drivers/transport/can_error.h"
#include "hcl_drivers/transport/udp_can_datagram.h"

using namespace hcl_drivers::transport;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  uint8_t kind = 0;
  const auto f = udp_can::decode(data, size, &kind);
  if (!f || kind != udp_can::kKindFrame) return 0;
  CanBusStatus st;
  if (f->error) st.apply(decodeErrorFrame(*f));
  const auto again = udp_can::encode(*f);
  // Same header, same id/dlc; unused data bytes are not carried (zero on re-encode).
  if (std::memcmp(again.data(), data, 9) != 0) std::abort();
  const auto back = udp_can::decode(again.data(), again.size());
  if (!back || !(*back == *f)) std::abort();
  return 0;
}
