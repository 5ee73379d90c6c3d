// SDO (CiA 301): read (upload) or write (download) one object dictionary entry.
// Expedited (up to 4 bytes, one request/response pair):
//   request  0x600+node: [cmd, index lo, index hi, subindex, data 4 bytes LE]
//     write: cmd 0x23/0x27/0x2B/0x2F for 4/3/2/1 bytes   read: cmd 0x40
//   response 0x580+node:
//     write acknowledged: 0x60; read: 0x43/0x47/0x4B/0x4F (4/3/2/1 bytes), 0x42 (size not indicated)
//     abort: 0x80 with the abort code (u32 LE) in bytes 4..7 (either side may send one)
// Segmented (any length; t = toggle bit, 0 in the first segment then alternating; n = number of
// the 7 data bytes that carry no data; c = 1 in the last segment):
//   upload:   response 0x41 [index, sub, size u32] (0x40: size not indicated), then per segment
//             request 0x60|t<<4 (bytes 1..7 zero), response t<<4|n<<1|c + 7 data bytes
//   download: request 0x21 [index, sub, size u32], response 0x60 [index, sub], then per segment
//             request t<<4|n<<1|c + 7 data bytes, response 0x20|t<<4 (bytes 1..7 zero)
// The master aborts with 0x05030000 on a toggle error and 0x05040000 on a timeout.
// Block transfers are not supported.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "hcl_drivers/transport/can_frame.h"

namespace hcl_drivers {
namespace canopen {

// Standard objects (CiA 301) the master reads.
constexpr uint16_t kDeviceNameIndex = 0x1008;  // manufacturer device name, VISIBLE_STRING (optional)
constexpr uint16_t kProducerHeartbeatIndex = 0x1017;  // producer heartbeat time, u16 ms

// Abort codes (CiA 301, table 22) this code names; others are reported in hex.
namespace sdo_abort {
constexpr uint32_t kToggleBit = 0x05030000;
constexpr uint32_t kTimeout = 0x05040000;
constexpr uint32_t kBadCommand = 0x05040001;
constexpr uint32_t kOutOfMemory = 0x05040005;
constexpr uint32_t kUnsupportedAccess = 0x06010000;
constexpr uint32_t kWriteOnly = 0x06010001;
constexpr uint32_t kReadOnly = 0x06010002;
constexpr uint32_t kNoObject = 0x06020000;
constexpr uint32_t kLengthMismatch = 0x06070010;
constexpr uint32_t kNoSubindex = 0x06090011;
constexpr uint32_t kValueRange = 0x06090030;
constexpr uint32_t kGeneral = 0x08000000;
constexpr uint32_t kDeviceState = 0x08000022;
}  // namespace sdo_abort
std::string describeAbort(uint32_t code);

// An SDO that failed: aborted by the node (abortCode() != 0), timed out or malformed.
class SdoError : public std::runtime_error {
 public:
  SdoError(const std::string& what, uint32_t abort_code = 0) : std::runtime_error(what), abort_code_(abort_code) {}
  uint32_t abortCode() const { return abort_code_; }

 private:
  uint32_t abort_code_;
};

transport::CanFrame encodeSdoRead(uint8_t node_id, uint16_t index, uint8_t subindex);
// size: 1..4 bytes of `value` (LE).
transport::CanFrame encodeSdoWrite(uint8_t node_id, uint16_t index, uint8_t subindex, uint32_t value, uint8_t size);

// Segmented transfer requests and the master's abort.
transport::CanFrame encodeSdoUploadSegmentRequest(uint8_t node_id, bool toggle);
transport::CanFrame encodeSdoDownloadInitiate(uint8_t node_id, uint16_t index, uint8_t subindex, uint32_t size);
// len: 0..7 bytes from `data`.
transport::CanFrame encodeSdoDownloadSegment(uint8_t node_id, bool toggle, const uint8_t* data, uint8_t len, bool last);
transport::CanFrame encodeSdoAbort(uint8_t node_id, uint16_t index, uint8_t subindex, uint32_t code);

struct SdoResponse {
  enum class Kind {
    kWriteAck,            // expedited write done, or segmented download initiated
    kReadData,            // expedited read: value, size
    kAbort,               // value = abort code
    kUploadSegmented,     // segmented upload initiated: value = size when size_indicated
    kUploadSegment,       // one segment: toggle, last, data[0..size)
    kDownloadSegmentAck,  // one segment acknowledged: toggle
  } kind = Kind::kAbort;
  uint16_t index = 0;       // not carried by segment frames (0 there)
  uint8_t subindex = 0;
  uint32_t value = 0;       // read data (zero-extended), abort code or segmented size
  uint8_t size = 0;         // read data size (4 when not indicated) or segment data length
  bool size_indicated = false;
  bool toggle = false;
  bool last = false;
  std::array<uint8_t, 7> data{};
  bool segment() const { return kind == Kind::kUploadSegment || kind == Kind::kDownloadSegmentAck; }
};
// Empty when `f` is not a well-formed SDO response (wrong length, RTR, unknown command).
std::optional<SdoResponse> decodeSdoResponse(const transport::CanFrame& f);


}  // namespace canopen
}  // namespace hcl_drivers
