#include "hcl_drivers/transport/udp_can_datagram.h"

#include "hcl_drivers/transport/can_error.h"

namespace hcl_drivers {
namespace transport {

namespace udp_can {

std::array<uint8_t, kDatagramSize> encode(const CanFrame& f) {
  std::array<uint8_t, kDatagramSize> d{};
  d[0] = 'C';
  d[1] = 'N';
  d[2] = kKindFrame;
  d[3] = static_cast<uint8_t>((f.rtr ? 1 : 0) | (f.extended ? 2 : 0) | (f.error ? 4 : 0));
  for (int i = 0; i < 4; ++i) d[4 + i] = static_cast<uint8_t>(f.id >> (8 * i));
  d[8] = f.dlc > 8 ? 8 : f.dlc;
  if (!f.rtr)
    for (int i = 0; i < d[8]; ++i) d[9 + i] = f.data[i];
  return d;
}

std::array<uint8_t, kDatagramSize> encodeHello() {
  std::array<uint8_t, kDatagramSize> d{};
  d[0] = 'C';
  d[1] = 'N';
  d[2] = kKindHello;
  return d;
}

std::optional<CanFrame> decode(const uint8_t* d, std::size_t n, uint8_t* kind) {
  if (n != kDatagramSize || d[0] != 'C' || d[1] != 'N') return std::nullopt;
  if (kind) *kind = d[2];
  if (d[2] == kKindHello) return CanFrame{};
  if (d[2] != kKindFrame || (d[3] & ~0x07) != 0 || d[8] > 8) return std::nullopt;
  CanFrame f;
  f.rtr = d[3] & 1;
  f.extended = d[3] & 2;
  f.error = d[3] & 4;
  f.id = static_cast<uint32_t>(d[4]) | (static_cast<uint32_t>(d[5]) << 8) | (static_cast<uint32_t>(d[6]) << 16) |
         (static_cast<uint32_t>(d[7]) << 24);
  const uint32_t limit = f.error ? can_err::kAll : (f.extended ? 0x1FFFFFFFu : 0x7FFu);
  if (f.id > limit) return std::nullopt;
  if (f.error && (f.rtr || f.extended)) return std::nullopt;
  f.dlc = d[8];
  if (!f.rtr)
    for (int i = 0; i < f.dlc; ++i) f.data[i] = d[9 + i];
  return f;
}

}  // namespace udp_can

}  // namespace transport
}  // namespace hcl_drivers
