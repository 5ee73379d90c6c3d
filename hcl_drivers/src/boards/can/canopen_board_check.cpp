// The hardware doctor's probe of a CANopen board (CanopenBoard::check, canopen_board.h).
#include <cstdio>
#include <string>

#include "canopen_board.h"
#include "hcl_drivers/transport/endpoint.h"

namespace hcl_drivers {

namespace {

std::string hex(uint32_t v, int digits) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%0*X", digits, v);
  return buf;
}

// An optional object: its value, or why not ("n/a: <abort>").
template <class Read>
std::string optionalObject(Read read) {
  try {
    return read();
  } catch (const canopen::SdoError& e) {
    return std::string("n/a (") + e.what() + ")";
  }
}

std::string text(const std::vector<uint8_t>& bytes) {
  std::string s(bytes.begin(), bytes.end());
  while (!s.empty() && (s.back() == '\0' || s.back() == ' ')) s.pop_back();
  return "'" + s + "'";
}

}  // namespace

void CanopenBoard::check(BoardContext& /*ctx*/, CheckReport& report) {
  const std::string url = url_;  // as configure() read them
  const int id = node_id_;
  const double timeout = std::max(0.1, sdo_timeout_);
  report.channel = {"can", url, id, false};
  const std::string expected_node = "node " + std::to_string(id) + " on " + url;
  std::shared_ptr<transport::CanBus> bus;
  try {
    bus = transport::openCanBus(url);
  } catch (const std::exception& e) {
    report.fail("bus", url, std::string("cannot open: ") + e.what(),
                "is the CAN interface there and up? (`ip -details link show`; make install-robot brings it up at boot)");
    return;
  }
  canopen::RemoteNode node(bus, static_cast<uint8_t>(id), extraCobIds());
  uint32_t device_type = 0;
  try {
    device_type = node.sdoRead(0x1000, 0, timeout);
  } catch (const canopen::SdoError& e) {
    if (e.abortCode() == 0) {
      report.fail("node", expected_node + " answers SDO 0x1000", "no answer (" + std::string(e.what()) + ")",
                  "is the board powered, on this bus, at this bitrate? A board at another node id is named below");
      return;
    }
    // An abort is an answer: the node is there, it only has no device type.
  }
  report.channel.answered = true;
  report.ok("node", expected_node + " answers SDO 0x1000", "device type " + hex(device_type, 8));

  auto u32 = [&](uint8_t sub) { return [&node, sub, timeout] { return hex(node.sdoRead(0x1018, sub, timeout), 8); }; };
  const std::string vendor = optionalObject(u32(1));
  const std::string product = optionalObject(u32(2));
  const std::string revision = optionalObject(u32(3));
  const std::string name = optionalObject([&] { return text(node.sdoUpload(canopen::kDeviceNameIndex, 0, timeout)); });
  const std::string software = optionalObject([&] { return text(node.sdoUpload(0x100A, 0, timeout)); });
  report.ok("identity", "0x1018 vendor/product/revision", "vendor " + vendor + ", product " + product + ", revision " +
                                                             revision + ", name " + name + ", firmware " + software);

  // A heartbeat (or boot-up) says the node runs its NMT state machine. A node without a producer
  // heartbeat gets one for the check (100 ms), then its setting back.
  node.pump();
  bool watched = node.heartbeatAge() >= 0.0;
  uint32_t heartbeat_ms = 0;
  std::string restore_error;
  if (!watched) {
    try {
      heartbeat_ms = node.sdoRead(canopen::kProducerHeartbeatIndex, 0, timeout);
      if (heartbeat_ms == 0) node.sdoWrite(canopen::kProducerHeartbeatIndex, 0, 100, 2, timeout);
      watched = node.waitFor([&] { return node.heartbeatAge() >= 0.0; }, std::max(0.5, 3.0 * heartbeat_ms / 1000.0));
      if (heartbeat_ms == 0) node.sdoWrite(canopen::kProducerHeartbeatIndex, 0, 0, 2, timeout);
    } catch (const canopen::SdoError& e) {
      restore_error = e.what();
    }
  }
  if (watched)
    report.ok("heartbeat", "a heartbeat or boot-up", std::string(canopen::toString(node.heartbeatState())) +
                                                         (heartbeat_ms ? ", every " + std::to_string(heartbeat_ms) + " ms" : ""));
  else
    report.fail("heartbeat", "a heartbeat or boot-up",
                restore_error.empty() ? "none within the wait" : "producer heartbeat 0x1017: " + restore_error,
                "the node answers SDO but sends no heartbeat: check its firmware's NMT (0x1017)");
}

}  // namespace hcl_drivers
