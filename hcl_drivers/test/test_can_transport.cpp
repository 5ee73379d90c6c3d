// CAN transports: the CAN-over-UDP wire format, the broadcast behaviour of the UDP bus (hub
// fan-out, no frame stealing, no echo to the sender, hub takeover), error frames and the bus
// state machine. UDP ports 27050..27059 (CAN's range).
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "hcl_drivers/transport/can_bus.h"
#include "hcl_drivers/transport/can_error.h"
#include "hcl_drivers/transport/udp_can_bus.h"

using namespace hcl_drivers::transport;

namespace {
std::shared_ptr<UdpCanBus> participant(uint16_t port) {
  return std::make_shared<UdpCanBus>("udp://127.0.0.1:" + std::to_string(port), "127.0.0.1", port);
}
void settle() { std::this_thread::sleep_for(std::chrono::milliseconds(80)); }  // HELLOs registered
}  // namespace

TEST(UdpCanWire, EncodesTheDocumentedLayout) {
  CanFrame f = CanFrame::make(0x18A, {1, 2, 3});
  const auto d = udp_can::encode(f);
  const std::array<uint8_t, 17> expect{'C', 'N', 1, 0, 0x8A, 0x01, 0, 0, 3, 1, 2, 3, 0, 0, 0, 0, 0};
  EXPECT_EQ(d, expect);
  CanFrame r = CanFrame::remote(0x181, 5);
  const auto dr = udp_can::encode(r);
  EXPECT_EQ(dr[3], 1);
  EXPECT_EQ(dr[8], 5);
  CanFrame x;
  x.id = 0x1ABCDEF0;
  x.extended = true;
  x.dlc = 1;
  x.data[0] = 0x55;
  const auto dx = udp_can::encode(x);
  EXPECT_EQ(dx[3], 2);
  EXPECT_EQ(dx[7], 0x1A);
}

TEST(UdpCanWire, RoundTripsEveryKind) {
  std::vector<CanFrame> frames{CanFrame::make(0x000, {0x01, 0x0A}), CanFrame::remote(0x7FF, 8), CanFrame::make(0x123, {}),
                               makeErrorFrame(can_err::kBusOff)};
  CanFrame x = CanFrame::make(0x12345, {9, 8, 7, 6, 5, 4, 3, 2});
  x.extended = true;
  frames.push_back(x);
  for (const auto& f : frames) {
    const auto d = udp_can::encode(f);
    uint8_t kind = 0;
    const auto back = udp_can::decode(d.data(), d.size(), &kind);
    ASSERT_TRUE(back) << toString(f);
    EXPECT_EQ(kind, udp_can::kKindFrame);
    EXPECT_EQ(*back, f) << toString(f) << " vs " << toString(*back);
  }
}

TEST(UdpCanWire, RejectsMalformedDatagrams) {
  auto d = udp_can::encode(CanFrame::make(0x181, {1}));
  EXPECT_FALSE(udp_can::decode(d.data(), 16));            // short
  auto bad = d;
  bad[0] = 'X';
  EXPECT_FALSE(udp_can::decode(bad.data(), bad.size()));  // magic
  bad = d;
  bad[2] = 7;
  EXPECT_FALSE(udp_can::decode(bad.data(), bad.size()));  // kind
  bad = d;
  bad[8] = 9;
  EXPECT_FALSE(udp_can::decode(bad.data(), bad.size()));  // dlc > 8
  bad = d;
  bad[5] = 0x08;                                          // id 0x881 > 11 bits
  EXPECT_FALSE(udp_can::decode(bad.data(), bad.size()));
  bad = d;
  bad[3] = 0x80;                                          // unknown flag
  EXPECT_FALSE(udp_can::decode(bad.data(), bad.size()));
  const auto hello = udp_can::encodeHello();
  uint8_t kind = 0;
  EXPECT_TRUE(udp_can::decode(hello.data(), hello.size(), &kind));
  EXPECT_EQ(kind, udp_can::kKindHello);
}

TEST(UdpCanBus, BroadcastsToEveryParticipantButTheSender) {
  auto hub = participant(27050);
  auto a = participant(27050);
  auto b = participant(27050);
  ASSERT_TRUE(hub->isHub());
  ASSERT_FALSE(a->isHub());
  ASSERT_FALSE(b->isHub());
  auto ch_hub = hub->open({});
  auto ch_a = a->open({});
  auto ch_b = b->open({});
  auto ch_b2 = b->open({});  // a second user in the same process
  settle();

  const CanFrame f = CanFrame::make(0x20A, {1, 2, 3, 4});
  ASSERT_TRUE(ch_a->send(f));
  CanFrame got;
  for (auto* ch : {ch_hub.get(), ch_b.get(), ch_b2.get()}) {
    ASSERT_TRUE(ch->receive(got, 1.0)) << ch->lastError();
    EXPECT_EQ(got, f);
  }
  EXPECT_FALSE(ch_a->receive(got, 0.1)) << "the sender must not get its own frame back";

  const CanFrame g = CanFrame::remote(0x18A, 8);
  ASSERT_TRUE(ch_b->send(g));  // from a client: the other local channel gets it too
  ASSERT_TRUE(ch_b2->receive(got, 1.0));
  EXPECT_EQ(got, g);
  ASSERT_TRUE(ch_a->receive(got, 1.0));
  EXPECT_EQ(got, g);
  ASSERT_TRUE(ch_hub->receive(got, 1.0));
  EXPECT_FALSE(ch_b->receive(got, 0.1));
}

TEST(UdpCanBus, AReceivedFrameCarriesTheKernelsReceiveTime) {
  // The time it reached the socket, not when its reader got to it: a reader that reads 200 ms
  // late still sees when the frame came.
  auto hub = participant(27052);
  auto a = participant(27052);
  auto rx = hub->open({});
  auto tx = a->open({});
  settle();
  const CanFrame f = CanFrame::make(0x18C, {7});
  EXPECT_EQ(f.received, 0.0);  // made here
  timeval before{};
  gettimeofday(&before, nullptr);
  ASSERT_TRUE(tx->send(f));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  CanFrame got;
  ASSERT_TRUE(rx->receive(got, 1.0)) << rx->lastError();
  EXPECT_EQ(got, f);  // the receive time is not part of the frame's identity
  const double sent = static_cast<double>(before.tv_sec) + 1e-6 * static_cast<double>(before.tv_usec);
  EXPECT_GE(got.received, sent - 0.001);
  EXPECT_LT(got.received, sent + 0.1);
}

TEST(UdpCanBus, FiltersDoNotStealFrames) {
  auto hub = participant(27051);
  auto a = participant(27051);
  auto node10 = hub->open({CanFilter{10, 0x7F}});
  auto node11 = hub->open({CanFilter{11, 0x7F}});
  auto everything = hub->open({});
  auto sender = a->open({});
  settle();
  ASSERT_TRUE(sender->send(CanFrame::make(0x18A, {1})));
  ASSERT_TRUE(sender->send(CanFrame::make(0x18B, {2})));
  CanFrame got;
  ASSERT_TRUE(node10->receive(got, 1.0));
  EXPECT_EQ(got.id, 0x18Au);
  EXPECT_FALSE(node10->receive(got, 0.1));
  ASSERT_TRUE(node11->receive(got, 1.0));
  EXPECT_EQ(got.id, 0x18Bu);
  ASSERT_TRUE(everything->receive(got, 1.0));
  EXPECT_EQ(got.id, 0x18Au);
  ASSERT_TRUE(everything->receive(got, 1.0));
  EXPECT_EQ(got.id, 0x18Bu);
}

TEST(UdpCanBus, AClientTakesOverWhenTheHubDies) {
  auto hub = participant(27052);
  auto a = participant(27052);
  auto b = participant(27052);
  auto ch_a = a->open({});
  auto ch_b = b->open({});
  settle();
  ch_a.reset();
  hub.reset();  // the hub process "dies"
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(3);
  while (!a->isHub() && !b->isHub() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_TRUE(a->isHub() || b->isHub());
  std::this_thread::sleep_for(std::chrono::milliseconds(400));  // keepalives reach the new hub
  auto ch_a2 = a->open({});
  ASSERT_TRUE(ch_b->send(CanFrame::make(0x123, {7})));
  CanFrame got;
  ASSERT_TRUE(ch_a2->receive(got, 1.0));
  EXPECT_EQ(got.data[0], 7);
}

TEST(UdpCanBus, ErrorFramesDriveTheBusStateAndMalformedDatagramsAreCounted) {
  auto hub = participant(27053);
  auto a = participant(27053);
  auto ch_a = a->open({});
  auto ch_hub = hub->open({});
  settle();
  ASSERT_TRUE(ch_a->send(makeErrorFrame(can_err::kBusOff)));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(1);
  while (hub->status().state != BusState::kBusOff && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_EQ(hub->status().state, BusState::kBusOff);
  EXPECT_EQ(hub->status().bus_off_count, 1u);
  EXPECT_FALSE(ch_hub->send(CanFrame::make(0x100, {1}))) << "a bus-off controller cannot send";
  EXPECT_NE(ch_hub->lastError().find("bus-off"), std::string::npos);
  ASSERT_TRUE(ch_a->send(makeErrorFrame(can_err::kRestarted)));
  while (hub->status().state != BusState::kErrorActive && std::chrono::steady_clock::now() < deadline + std::chrono::seconds(1))
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_EQ(hub->status().state, BusState::kErrorActive);
  EXPECT_TRUE(ch_hub->send(CanFrame::make(0x100, {1})));

  // Garbage on the hub's port: counted, dropped, nothing delivered.
  UdpCanBus* raw = hub.get();
  const auto before = raw->status().malformed;
  int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(27053);
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const char garbage[] = "not a CAN frame";
  ::sendto(fd, garbage, sizeof(garbage), 0, reinterpret_cast<sockaddr*>(&to), sizeof(to));
  ::close(fd);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(raw->status().malformed, before + 1);
  CanFrame got;
  EXPECT_FALSE(ch_hub->receive(got, 0.05));
}

TEST(CanError, DecodesSocketCanErrorClasses) {
  auto e = decodeErrorFrame(makeErrorFrame(can_err::kBusOff));
  EXPECT_TRUE(e.bus_off);
  e = decodeErrorFrame(makeErrorFrame(can_err::kController, can_err::kCtrlTxPassive));
  EXPECT_TRUE(e.passive);
  EXPECT_FALSE(e.bus_off);
  e = decodeErrorFrame(makeErrorFrame(can_err::kController, can_err::kCtrlRxWarning));
  EXPECT_TRUE(e.warning);
  e = decodeErrorFrame(makeErrorFrame(can_err::kRestarted));
  EXPECT_TRUE(e.restarted);
  CanFrame c = makeErrorFrame(can_err::kCounters | can_err::kProtocol);
  c.data[6] = 130;
  c.data[7] = 7;
  e = decodeErrorFrame(c);
  EXPECT_TRUE(e.has_counters);
  EXPECT_EQ(e.tx_errors, 130);
  EXPECT_EQ(e.rx_errors, 7);
  EXPECT_TRUE(e.protocol);
  EXPECT_FALSE(decodeErrorFrame(CanFrame::make(0x40, {1, 0x20})).bus_off) << "a data frame is no error frame";
}

TEST(CanError, BusStateMachine) {
  CanBusStatus s;
  s.apply(decodeErrorFrame(makeErrorFrame(can_err::kController, can_err::kCtrlTxWarning)));
  EXPECT_EQ(s.state, BusState::kWarning);
  s.apply(decodeErrorFrame(makeErrorFrame(can_err::kController, can_err::kCtrlTxPassive)));
  EXPECT_EQ(s.state, BusState::kErrorPassive);
  EXPECT_EQ(s.passive_count, 1u);
  s.apply(decodeErrorFrame(makeErrorFrame(can_err::kBusOff)), 100.0);
  EXPECT_EQ(s.state, BusState::kBusOff);
  s.apply(decodeErrorFrame(makeErrorFrame(can_err::kController, can_err::kCtrlTxPassive)), 100.1);
  EXPECT_EQ(s.state, BusState::kBusOff) << "passive reports do not lift bus-off";
  s.frameReceived(100.2);
  EXPECT_EQ(s.state, BusState::kBusOff) << "a frame in flight at the bus-off proves nothing";
  s.frameReceived(100.6);
  EXPECT_EQ(s.state, BusState::kErrorActive) << "receiving well after means the controller restarted";
  EXPECT_EQ(s.restarts, 1u);
  s.apply(decodeErrorFrame(makeErrorFrame(can_err::kBusOff)));
  s.apply(decodeErrorFrame(makeErrorFrame(can_err::kRestarted)));
  EXPECT_EQ(s.state, BusState::kErrorActive);
  EXPECT_EQ(s.bus_off_count, 2u);
  EXPECT_EQ(s.error_frames, 6u);
}

TEST(CanFrame, CandumpStyleText) {
  EXPECT_EQ(toString(CanFrame::make(0x18A, {0x01, 0xAB})), "18A#01AB");
  EXPECT_EQ(toString(CanFrame::remote(0x181, 5)), "181#R5");
}

TEST(OpenCanBus, SharesOneBusPerUrlAndRejectsBadUrls) {
  auto a = openCanBus("udp://127.0.0.1:27054");
  auto b = openCanBus("udp://127.0.0.1:27054");
  EXPECT_EQ(a.get(), b.get());
  EXPECT_THROW(openCanBus("tcp://x"), std::invalid_argument);
  EXPECT_THROW(openCanBus("/dev/i2c-1"), std::invalid_argument);
}
