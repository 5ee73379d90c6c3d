// PDOs: process data, up to 8 bytes, little endian (CiA 301). A TPDO is requested from a
// node with a remote frame (RTR) on its COB-ID; an RPDO is sent to the node.
#pragma once

#include <cstdint>
#include <vector>

#include "hcl_drivers/transport/can_frame.h"

namespace hcl_drivers {
namespace canopen {

using transport::CanFrame;

inline CanFrame encodePdo(uint32_t cob_id, const std::vector<uint8_t>& bytes) {
  CanFrame f;
  f.id = cob_id & 0x7FF;
  f.dlc = static_cast<uint8_t>(bytes.size() > 8 ? 8 : bytes.size());
  for (int i = 0; i < f.dlc; ++i) f.data[i] = bytes[i];
  return f;
}

// The remote frame requesting TPDO `cob_id` of `dlc` bytes.
inline CanFrame encodeRtr(uint32_t cob_id, uint8_t dlc) { return CanFrame::remote(cob_id & 0x7FF, dlc); }

// Little-endian helpers: callers check the frame length first.
inline uint16_t getU16(const CanFrame& f, int at) {
  return static_cast<uint16_t>(f.data[at] | (f.data[at + 1] << 8));
}
inline int16_t getI16(const CanFrame& f, int at) { return static_cast<int16_t>(getU16(f, at)); }
inline uint32_t getU32(const CanFrame& f, int at) {
  return static_cast<uint32_t>(f.data[at]) | (static_cast<uint32_t>(f.data[at + 1]) << 8) |
         (static_cast<uint32_t>(f.data[at + 2]) << 16) | (static_cast<uint32_t>(f.data[at + 3]) << 24);
}
inline int32_t getI32(const CanFrame& f, int at) { return static_cast<int32_t>(getU32(f, at)); }
inline void putU16(std::vector<uint8_t>& b, uint16_t v) {
  b.push_back(static_cast<uint8_t>(v));
  b.push_back(static_cast<uint8_t>(v >> 8));
}
inline void putU32(std::vector<uint8_t>& b, uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<uint8_t>(v >> (8 * i)));
}

}  // namespace canopen
}  // namespace hcl_drivers
