// The CAN-over-UDP bus's datagram (udp_can_bus.h): one CAN frame per datagram, encoded and
// decoded here alone, so the decoder is fuzzed without the bus's sockets and threads.
//
// Wire format: one CAN frame per datagram, 17 bytes, little endian:
//   0  'C'  1  'N'        magic
//   2  kind               1 = frame, 2 = HELLO (keepalive; bytes 3..16 zero)
//   3  flags              bit0 RTR, bit1 extended id, bit2 error frame (linux/can/error.h layout)
//   4  id  (u32 LE)       11-bit, 29-bit or error class bits
//   8  dlc                0..8
//   9  data[8]            unused bytes zero
// Anything else (wrong size, magic, kind, dlc > 8, id too wide) is counted as malformed and dropped.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "hcl_drivers/transport/can_frame.h"

namespace hcl_drivers {
namespace transport {

namespace udp_can {
constexpr std::size_t kDatagramSize = 17;
constexpr uint8_t kKindFrame = 1;
constexpr uint8_t kKindHello = 2;
std::array<uint8_t, kDatagramSize> encode(const CanFrame& f);
std::array<uint8_t, kDatagramSize> encodeHello();
// kind in `kind`; the frame when kind == frame. Empty when malformed.
std::optional<CanFrame> decode(const uint8_t* data, std::size_t size, uint8_t* kind = nullptr);
}  // namespace udp_can

}  // namespace transport
}  // namespace hcl_drivers
