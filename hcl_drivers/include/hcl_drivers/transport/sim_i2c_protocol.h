// Packets of the simulated I2C bus (sim:///PATH, a Unix SOCK_SEQPACKET socket). One request
// packet carries one combined transaction, exactly what one ioctl(I2C_RDWR) carries:
//
//   request : 'I' 'Q' seq(u16) count(u8) { address(u8) flags(u8) length(u16) [data if write] } x count
//             flags bit 0 = read (I2C_M_RD)
//   response: 'I' 'A' seq(u16) status(u8) [the bytes of every read message, in order]
//             status 0 = ok, 1 = NACK (no device acknowledged an address byte), 2 = bus error
//
// The emulator answers every request in order; `seq` lets the master drop answers to
// requests it already gave up on (timeouts). Integers are little-endian.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "hcl_drivers/transport/i2c_bus.h"

namespace hcl_drivers {
namespace transport {
namespace sim_i2c {

constexpr uint8_t kMagic = 'I';
constexpr uint8_t kRequest = 'Q';
constexpr uint8_t kAnswer = 'A';
constexpr uint8_t kFlagRead = 0x01;
constexpr uint8_t kStatusOk = 0;
constexpr uint8_t kStatusNack = 1;
constexpr uint8_t kStatusBusError = 2;
constexpr std::size_t kMaxPacket = 4096;

std::vector<uint8_t> encodeRequest(uint16_t seq, const std::vector<I2cMessage>& msgs);

struct Answer {
  uint16_t seq = 0;
  uint8_t status = 0;
  std::vector<uint8_t> read_bytes;
};
// Empty when the packet is not a well-formed answer.
std::optional<Answer> decodeAnswer(const uint8_t* data, std::size_t n);

}  // namespace sim_i2c
}  // namespace transport
}  // namespace hcl_drivers
