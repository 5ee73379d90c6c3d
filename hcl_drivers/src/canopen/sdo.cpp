#include "hcl_drivers/canopen/sdo.h"

#include <cstdio>

#include "hcl_drivers/canopen/cob_id.h"

namespace hcl_drivers {
namespace canopen {

using transport::CanFrame;

std::string describeAbort(uint32_t code) {
  const char* text = nullptr;
  switch (code) {
    case sdo_abort::kToggleBit: text = "toggle bit not alternated"; break;
    case sdo_abort::kTimeout: text = "SDO protocol timed out"; break;
    case sdo_abort::kBadCommand: text = "command specifier not valid or unknown"; break;
    case sdo_abort::kOutOfMemory: text = "out of memory"; break;
    case sdo_abort::kUnsupportedAccess: text = "unsupported access to an object"; break;
    case sdo_abort::kWriteOnly: text = "attempt to read a write only object"; break;
    case sdo_abort::kReadOnly: text = "attempt to write a read only object"; break;
    case sdo_abort::kNoObject: text = "object does not exist in the object dictionary"; break;
    case sdo_abort::kLengthMismatch: text = "data type does not match, length of service parameter does not match"; break;
    case sdo_abort::kNoSubindex: text = "sub-index does not exist"; break;
    case sdo_abort::kValueRange: text = "value range of parameter exceeded"; break;
    case sdo_abort::kGeneral: text = "general error"; break;
    case sdo_abort::kDeviceState: text = "data cannot be transferred because of the present device state"; break;
    default: break;
  }
  char buf[32];
  std::snprintf(buf, sizeof(buf), "0x%08X", code);
  return std::string(buf) + (text ? std::string(" (") + text + ")" : std::string(" (unknown abort code)"));
}

CanFrame encodeSdoRead(uint8_t node_id, uint16_t index, uint8_t subindex) {
  return CanFrame::make(kSdoRx + (node_id & 0x7F), {0x40, static_cast<uint8_t>(index), static_cast<uint8_t>(index >> 8),
                                                     subindex, 0, 0, 0, 0});
}

CanFrame encodeSdoWrite(uint8_t node_id, uint16_t index, uint8_t subindex, uint32_t value, uint8_t size) {
  if (size < 1 || size > 4) size = 4;
  const uint8_t cmd = static_cast<uint8_t>(0x23 | ((4 - size) << 2));
  CanFrame f = CanFrame::make(kSdoRx + (node_id & 0x7F),
                              {cmd, static_cast<uint8_t>(index), static_cast<uint8_t>(index >> 8), subindex, 0, 0, 0, 0});
  for (int i = 0; i < size; ++i) f.data[4 + i] = static_cast<uint8_t>(value >> (8 * i));
  return f;
}

CanFrame encodeSdoUploadSegmentRequest(uint8_t node_id, bool toggle) {
  return CanFrame::make(kSdoRx + (node_id & 0x7F), {static_cast<uint8_t>(0x60 | (toggle ? 0x10 : 0)), 0, 0, 0, 0, 0, 0, 0});
}

CanFrame encodeSdoDownloadInitiate(uint8_t node_id, uint16_t index, uint8_t subindex, uint32_t size) {
  CanFrame f = CanFrame::make(kSdoRx + (node_id & 0x7F),
                              {0x21, static_cast<uint8_t>(index), static_cast<uint8_t>(index >> 8), subindex, 0, 0, 0, 0});
  for (int i = 0; i < 4; ++i) f.data[4 + i] = static_cast<uint8_t>(size >> (8 * i));
  return f;
}

CanFrame encodeSdoDownloadSegment(uint8_t node_id, bool toggle, const uint8_t* data, uint8_t len, bool last) {
  if (len > 7) len = 7;
  CanFrame f = CanFrame::make(kSdoRx + (node_id & 0x7F), {0, 0, 0, 0, 0, 0, 0, 0});
  f.data[0] = static_cast<uint8_t>((toggle ? 0x10 : 0) | ((7 - len) << 1) | (last ? 1 : 0));
  for (int i = 0; i < len; ++i) f.data[1 + i] = data[i];
  return f;
}

CanFrame encodeSdoAbort(uint8_t node_id, uint16_t index, uint8_t subindex, uint32_t code) {
  CanFrame f = CanFrame::make(kSdoRx + (node_id & 0x7F),
                              {0x80, static_cast<uint8_t>(index), static_cast<uint8_t>(index >> 8), subindex, 0, 0, 0, 0});
  for (int i = 0; i < 4; ++i) f.data[4 + i] = static_cast<uint8_t>(code >> (8 * i));
  return f;
}

std::optional<SdoResponse> decodeSdoResponse(const CanFrame& f) {
  if (f.error || f.rtr || f.extended || functionOf(f.id) != kSdoTx || f.dlc != 8) return std::nullopt;
  SdoResponse r;
  r.index = static_cast<uint16_t>(f.data[1] | (f.data[2] << 8));
  r.subindex = f.data[3];
  const uint32_t payload = static_cast<uint32_t>(f.data[4]) | (static_cast<uint32_t>(f.data[5]) << 8) |
                           (static_cast<uint32_t>(f.data[6]) << 16) | (static_cast<uint32_t>(f.data[7]) << 24);
  const uint8_t cmd = f.data[0];
  if ((cmd & 0xE0) == 0x00) {  // upload segment (scs = 0): no index in the frame
    r.index = 0;
    r.subindex = 0;
    r.kind = SdoResponse::Kind::kUploadSegment;
    r.toggle = cmd & 0x10;
    r.last = cmd & 0x01;
    r.size = static_cast<uint8_t>(7 - ((cmd >> 1) & 7));
    for (int i = 0; i < 7; ++i) r.data[i] = i < r.size ? f.data[1 + i] : 0;
    return r;
  }
  if ((cmd & 0xE0) == 0x20) {  // download segment acknowledged (scs = 1)
    if (cmd & 0x0F) return std::nullopt;  // reserved bits
    r.index = 0;
    r.subindex = 0;
    r.kind = SdoResponse::Kind::kDownloadSegmentAck;
    r.toggle = cmd & 0x10;
    return r;
  }
  if (cmd == 0x60) {
    r.kind = SdoResponse::Kind::kWriteAck;
  } else if (cmd == 0x80) {
    r.kind = SdoResponse::Kind::kAbort;
    r.value = payload;
  } else if ((cmd & 0xE0) == 0x40) {  // upload response (scs = 2)
    const bool expedited = cmd & 0x02, size_indicated = cmd & 0x01;
    if (cmd & 0x10) return std::nullopt;  // reserved bit
    if (!expedited) {  // segmented upload initiated
      if (cmd & 0x0C) return std::nullopt;  // n is only meaningful with e = 1
      r.kind = SdoResponse::Kind::kUploadSegmented;
      r.size_indicated = size_indicated;
      r.value = size_indicated ? payload : 0;
      return r;
    }
    r.kind = SdoResponse::Kind::kReadData;
    r.size = size_indicated ? static_cast<uint8_t>(4 - ((cmd >> 2) & 3)) : 4;
    r.value = r.size == 4 ? payload : (payload & ((1u << (8 * r.size)) - 1));
  } else {
    return std::nullopt;
  }
  return r;
}

}  // namespace canopen
}  // namespace hcl_drivers
