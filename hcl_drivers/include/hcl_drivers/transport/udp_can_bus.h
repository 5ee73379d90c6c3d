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
// Wire format: udp_can_datagram.h.
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
#include "hcl_drivers/transport/udp_can_datagram.h"

namespace hcl_drivers {
namespace transport {

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
