// libFuzzer target: every CAN frame decoder of the CANopen layer and the CAN boards, and the
// RemoteNode dispatcher fed arbitrary frames through an in-memory bus. Must never crash, hang
// or trip ASan/UBSan, whatever the bytes.
// Input: a sequence of 11-byte records [id lo, id hi (3 bits used), flags, dlc, data 0..7]:
// flags bit0 RTR, bit1 extended, bit2 error.
#include <cstddef>
#include <cstdint>
#include <deque>

#include "epos_protocol.h"
#include "hcl_drivers/canopen/canopen.h"
#include "hcl_drivers/transport/can_error.h"
#include "hmi_board_protocol.h"
#include "motor_board_protocol.h"
#include "servo_board_protocol.h"
#include "stepper_board_protocol.h"

using namespace hcl_drivers;
using transport::CanFrame;

namespace {

// A bus whose only channel returns the fuzzer's frames, then times out.
class FuzzChannel : public transport::CanChannel {
 public:
  std::deque<CanFrame> frames;
  bool send(const CanFrame&) override { return true; }
  bool receive(CanFrame& f, double) override {
    if (frames.empty()) return false;
    f = frames.front();
    frames.pop_front();
    return true;
  }
  void drain() override { frames.clear(); }
};
class FuzzBus : public transport::CanBus {
 public:
  FuzzBus() : CanBus("fuzz://") {}
  std::shared_ptr<transport::CanChannel> open(const std::vector<transport::CanFilter>&) override { return channel; }
  std::shared_ptr<FuzzChannel> channel = std::make_shared<FuzzChannel>();
};

CanFrame frameFrom(const uint8_t* d) {
  CanFrame f;
  f.extended = d[2] & 2;
  f.rtr = d[2] & 1;
  f.error = d[2] & 4;
  f.id = (static_cast<uint32_t>(d[0]) | (static_cast<uint32_t>(d[1]) << 8)) & (f.extended ? 0x1FFFFFFF : 0x7FF);
  f.dlc = d[3] % 9;
  for (int i = 0; i < 8; ++i) f.data[i] = d[3 + (i + 1) % 8];
  return f;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto bus = std::make_shared<FuzzBus>();
  canopen::RemoteNode node(bus, 10, {0x381});
  node.onFrame(0x18A, [](const CanFrame& f) { return motor_board::decodeEncoders(f).has_value(); });
  node.onFrame(0x28A, [](const CanFrame& f) { return motor_board::decodeStatus(f).has_value(); });
  node.onFrame(0x381, [](const CanFrame& f) { return epos::decodeFeedback(f).has_value(); });
  for (size_t at = 0; at + 11 <= size; at += 11) {
    const CanFrame f = frameFrom(data + at);
    // Stand-alone decoders.
    canopen::decodeNmt(f);
    canopen::decodeHeartbeat(f);
    if (auto r = canopen::decodeSdoResponse(f)) canopen::describeAbort(r->value);
    transport::CanBusStatus st;
    st.apply(transport::decodeErrorFrame(f));
    st.frameReceived();
    transport::toString(f);
    motor_board::decodeEncoders(f);
    motor_board::decodeStatus(f);
    stepper_board::decodePositions(f);
    stepper_board::decodeSwitches(f);
    if (auto a = servo_board::decodeRangers(f))
      for (uint16_t v : *a) servo_board::gp2d12Metres(v);
    servo_board::decodeSwitches(f);
    if (auto s = epos::decodeStatus(f)) epos::toString(epos::decodeDriveState(s->statusword));
    epos::decodeFeedback(f);
    hmi_board::decodeKeys(f);
    bus->channel->frames.push_back(f);
  }
  // The dispatcher, including SDO matching: an SDO read consumes the queued frames.
  node.pump();
  for (size_t at = 0; at + 11 <= size; at += 11) bus->channel->frames.push_back(frameFrom(data + at));
  try {
    node.sdoRead(0x2002, 0, 0.0);
  } catch (const canopen::SdoError&) {
  }
  // The segmented upload state machine (toggle, length, abort) over the same frames again.
  for (size_t at = 0; at + 11 <= size; at += 11) bus->channel->frames.push_back(frameFrom(data + at));
  try {
    node.sdoUpload(0x1008, 0, 0.0);
  } catch (const canopen::SdoError&) {
  }
  return 0;
}
