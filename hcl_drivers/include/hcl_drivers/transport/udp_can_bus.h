// CAN over UDP on loopback: a broadcast CAN bus for machines without vcan, carrying the same
// frames as SocketCAN. Every process on the bus (drivers, emulators, candump-like tools) is a
// participant of the bus `udp://127.0.0.1:PORT`:
//
//   * the first participant that can bind PORT becomes the HUB; the others bind an ephemeral
//     port and send every frame to the hub, plus a HELLO keepalive every 200 ms;
//   * the hub forwards each frame it receives to every other known participant (a peer is
//     forgotten after 2 s without a datagram) and delivers it to its own local channels;
//   * when the hub process dies, the next participant whose periodic bind() of PORT succeeds
//     (tried every 300 ms) becomes the hub; the keepalives re-register everyone with it, so the
//     bus heals within ~0.5 s and a dead emulator process looks like an unplugged board.
//   * within one process, frames are delivered locally to every other channel (not to the
//     sender), like SocketCAN's local loopback.
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

#include <netinet/in.h>

#include <array>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <map>
#include <optional>
#include <thread>

#include "hcl_drivers/transport/can_bus.h"

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

class UdpCanBus : public CanBus, public std::enable_shared_from_this<UdpCanBus> {
 public:
  UdpCanBus(const std::string& url, const std::string& host, uint16_t port);
  ~UdpCanBus() override;
  std::shared_ptr<CanChannel> open(const std::vector<CanFilter>& filters) override;

  bool isHub() const { return hub_; }

  class Channel;
  bool sendFrom(Channel* sender, const CanFrame& f, std::string& error);
  void close(Channel* ch);

 private:
  void run();
  bool tryBecomeHub();
  void deliverLocal(const CanFrame& f, const Channel* except);
  void handleDatagram(const uint8_t* buf, std::size_t n, const sockaddr_in& from, double received);

  sockaddr_in hub_addr_{};
  std::atomic<int> fd_{-1};
  std::atomic<bool> hub_{false};
  std::atomic<bool> running_{true};
  std::thread thread_;
  std::mutex mutex_;  // channels_ and peers_
  std::vector<Channel*> channels_;
  std::map<uint64_t, std::pair<sockaddr_in, double>> peers_;  // hub only: addr -> last seen [s]
};

}  // namespace transport
}  // namespace hcl_drivers
