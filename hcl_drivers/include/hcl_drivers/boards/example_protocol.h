// Wire format of the skeleton's example board (one UDP datagram each way).
//
//   request  (5 bytes):  'E' 'X' 0x01 seq lamp_pwm
//   response (11 bytes): 'E' 'X' 0x81 seq dial_raw(u16 LE) lamp_pwm uptime_ms(u32 LE)
//
// The board answers every request with its current variables and applies lamp_pwm.
// `seq` pairs an answer with its request, so a late answer is never taken for a new one.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

namespace hcl_drivers {
namespace example_protocol {

constexpr uint8_t kMagic0 = 'E';
constexpr uint8_t kMagic1 = 'X';
constexpr uint8_t kOpExchange = 0x01;
constexpr uint8_t kOpExchangeReply = 0x81;
constexpr std::size_t kRequestSize = 5;
constexpr std::size_t kReplySize = 11;
constexpr uint16_t kDialMax = 1023;

struct Reply {
  uint8_t seq = 0;
  uint16_t dial_raw = 0;
  uint8_t lamp_pwm = 0;
  uint32_t uptime_ms = 0;
};

inline std::vector<uint8_t> encodeRequest(uint8_t seq, uint8_t lamp_pwm) {
  return {kMagic0, kMagic1, kOpExchange, seq, lamp_pwm};
}

// Empty when the datagram is not a well-formed reply (wrong size, magic or opcode,
// dial out of range).
inline std::optional<Reply> decodeReply(const std::vector<uint8_t>& d) {
  if (d.size() != kReplySize || d[0] != kMagic0 || d[1] != kMagic1 || d[2] != kOpExchangeReply) return std::nullopt;
  Reply r;
  r.seq = d[3];
  r.dial_raw = static_cast<uint16_t>(d[4] | (d[5] << 8));
  r.lamp_pwm = d[6];
  r.uptime_ms = static_cast<uint32_t>(d[7]) | (static_cast<uint32_t>(d[8]) << 8) | (static_cast<uint32_t>(d[9]) << 16) |
                (static_cast<uint32_t>(d[10]) << 24);
  if (r.dial_raw > kDialMax) return std::nullopt;
  return r;
}

}  // namespace example_protocol
}  // namespace hcl_drivers
