// The CANopen master layer: every NMT and SDO path, byte-exact, and RemoteNode against a
// scripted node on a CAN-over-UDP bus (SDO aborts and timeouts surfaced as SdoError, boot-up
// consumption, malformed and unknown frames counted). UDP ports 27055..27059.
#include <gtest/gtest.h>

#include <atomic>
#include <algorithm>
#include <string>
#include <mutex>
#include <thread>

#include "hcl_drivers/canopen/canopen.h"
#include "hcl_drivers/transport/udp_can_bus.h"

using namespace hcl_drivers;
using namespace hcl_drivers::canopen;
using transport::CanFrame;

namespace {
std::vector<uint8_t> bytes(const CanFrame& f) { return std::vector<uint8_t>(f.data.begin(), f.data.begin() + f.dlc); }
CanFrame sdoReply(uint8_t node, std::initializer_list<uint8_t> b) { return CanFrame::make(0x580 + node, b); }
}  // namespace

TEST(Nmt, EncodesEveryCommand) {
  const std::pair<NmtCommand, uint8_t> cmds[] = {{NmtCommand::kStart, 0x01}, {NmtCommand::kStop, 0x02},
                                                 {NmtCommand::kEnterPreOperational, 0x80}, {NmtCommand::kResetNode, 0x81},
                                                 {NmtCommand::kResetCommunication, 0x82}};
  for (const auto& c : cmds) {
    const CanFrame f = encodeNmt(c.first, 10);
    EXPECT_EQ(f.id, 0x000u);
    EXPECT_EQ(bytes(f), (std::vector<uint8_t>{c.second, 10}));
    const auto back = decodeNmt(f);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->command, c.first);
    EXPECT_EQ(back->node_id, 10);
  }
  EXPECT_FALSE(decodeNmt(CanFrame::make(0x000, {0x03, 10})));
  EXPECT_FALSE(decodeNmt(CanFrame::make(0x000, {0x01})));
  EXPECT_FALSE(decodeNmt(CanFrame::make(0x001, {0x01, 1})));
}

TEST(Nmt, DecodesHeartbeatsAndBootUp) {
  auto hb = decodeHeartbeat(CanFrame::make(0x70A, {0x00}));
  ASSERT_TRUE(hb);
  EXPECT_TRUE(hb->bootUp());
  EXPECT_EQ(hb->node_id, 10);
  EXPECT_EQ(decodeHeartbeat(CanFrame::make(0x70A, {0x05}))->state, NmtState::kOperational);
  EXPECT_EQ(decodeHeartbeat(CanFrame::make(0x70A, {0x7F}))->state, NmtState::kPreOperational);
  EXPECT_EQ(decodeHeartbeat(CanFrame::make(0x70A, {0x84}))->state, NmtState::kStopped) << "toggle bit ignored";
  EXPECT_FALSE(decodeHeartbeat(CanFrame::make(0x70A, {0x06})));
  EXPECT_FALSE(decodeHeartbeat(CanFrame::make(0x70A, {0x05, 0})));
  EXPECT_FALSE(decodeHeartbeat(CanFrame::make(0x700, {0x05})));
  EXPECT_FALSE(decodeHeartbeat(CanFrame::remote(0x70A, 1)));
  EXPECT_EQ(bytes(encodeHeartbeat(3, NmtState::kOperational)), std::vector<uint8_t>{0x05});
  EXPECT_EQ(encodeHeartbeat(3, NmtState::kOperational).id, 0x703u);
}

TEST(Sdo, EncodesExpeditedRequests) {
  const CanFrame r = encodeSdoRead(10, 0x2001, 0x02);
  EXPECT_EQ(r.id, 0x60Au);
  EXPECT_EQ(bytes(r), (std::vector<uint8_t>{0x40, 0x01, 0x20, 0x02, 0, 0, 0, 0}));
  EXPECT_EQ(bytes(encodeSdoWrite(1, 0x6060, 0, 3, 1)), (std::vector<uint8_t>{0x2F, 0x60, 0x60, 0, 3, 0, 0, 0}));
  EXPECT_EQ(bytes(encodeSdoWrite(1, 0x2001, 0, 200, 2)), (std::vector<uint8_t>{0x2B, 0x01, 0x20, 0, 200, 0, 0, 0}));
  EXPECT_EQ(bytes(encodeSdoWrite(1, 0x2001, 0, 0x123456, 3)), (std::vector<uint8_t>{0x27, 0x01, 0x20, 0, 0x56, 0x34, 0x12, 0}));
  EXPECT_EQ(bytes(encodeSdoWrite(1, 0x1017, 0, 0xA1B2C3D4, 4)),
            (std::vector<uint8_t>{0x23, 0x17, 0x10, 0, 0xD4, 0xC3, 0xB2, 0xA1}));
}

TEST(Sdo, DecodesEveryResponseKind) {
  auto r = decodeSdoResponse(sdoReply(1, {0x60, 0x60, 0x60, 0, 0, 0, 0, 0}));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->kind, SdoResponse::Kind::kWriteAck);
  EXPECT_EQ(r->index, 0x6060);
  r = decodeSdoResponse(sdoReply(1, {0x4F, 0x61, 0x60, 0, 0xFD, 0xAA, 0xAA, 0xAA}));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->kind, SdoResponse::Kind::kReadData);
  EXPECT_EQ(r->size, 1);
  EXPECT_EQ(r->value, 0xFDu) << "bytes beyond the indicated size are ignored";
  r = decodeSdoResponse(sdoReply(1, {0x4B, 0x02, 0x20, 0, 0x03, 0x01, 0xAA, 0xAA}));
  EXPECT_EQ(r->size, 2);
  EXPECT_EQ(r->value, 0x0103u);
  r = decodeSdoResponse(sdoReply(1, {0x47, 0x02, 0x20, 0, 1, 2, 3, 0xAA}));
  EXPECT_EQ(r->size, 3);
  EXPECT_EQ(r->value, 0x030201u);
  r = decodeSdoResponse(sdoReply(1, {0x43, 0x00, 0x10, 0, 1, 2, 3, 4}));
  EXPECT_EQ(r->size, 4);
  EXPECT_EQ(r->value, 0x04030201u);
  r = decodeSdoResponse(sdoReply(1, {0x42, 0x00, 0x10, 0, 1, 2, 3, 4}));
  EXPECT_EQ(r->kind, SdoResponse::Kind::kReadData);
  EXPECT_EQ(r->size, 4) << "size not indicated: 4 bytes";
  r = decodeSdoResponse(sdoReply(1, {0x80, 0x34, 0x12, 5, 0x00, 0x00, 0x02, 0x06}));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->kind, SdoResponse::Kind::kAbort);
  EXPECT_EQ(r->value, sdo_abort::kNoObject);
  EXPECT_EQ(r->index, 0x1234);
  EXPECT_EQ(r->subindex, 5);
  r = decodeSdoResponse(sdoReply(1, {0x41, 0x08, 0x10, 0, 20, 0, 0, 0}));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->kind, SdoResponse::Kind::kUploadSegmented) << "a segmented upload";
  EXPECT_TRUE(r->size_indicated);
  EXPECT_EQ(r->value, 20u);
  EXPECT_EQ(r->index, 0x1008);
  EXPECT_FALSE(decodeSdoResponse(sdoReply(1, {0x60, 0, 0, 0})));           // wrong length
  // (Not 0x20: from the server it is a download segment acknowledge, see SdoSegmented.)
  EXPECT_FALSE(decodeSdoResponse(sdoReply(1, {0xA0, 0, 0, 0, 0, 0, 0, 0})));  // block upload: not supported
  EXPECT_FALSE(decodeSdoResponse(sdoReply(1, {0xC0, 0, 0, 0, 0, 0, 0, 0})));  // block download: not supported
  EXPECT_FALSE(decodeSdoResponse(CanFrame::make(0x601, {0x60, 0, 0, 0, 0, 0, 0, 0})));
  EXPECT_NE(describeAbort(sdo_abort::kNoObject).find("does not exist"), std::string::npos);
  EXPECT_NE(describeAbort(0x12345678).find("0x12345678"), std::string::npos);
}

// Segmented SDO frames, byte-exact against CiA 301 (7.2.4.3.3 - 7.2.4.3.7).
TEST(SdoSegmented, EncodesClientRequests) {
  EXPECT_EQ(bytes(encodeSdoUploadSegmentRequest(10, false)), (std::vector<uint8_t>{0x60, 0, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(bytes(encodeSdoUploadSegmentRequest(10, true)), (std::vector<uint8_t>{0x70, 0, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(encodeSdoUploadSegmentRequest(10, true).id, 0x60Au);
  // initiate download, segmented, size indicated: ccs=1, e=0, s=1 -> 0x21, size in bytes 4..7
  EXPECT_EQ(bytes(encodeSdoDownloadInitiate(10, 0x2100, 0, 18)), (std::vector<uint8_t>{0x21, 0x00, 0x21, 0, 18, 0, 0, 0}));
  const uint8_t text[] = {'a', 'b', 'c', 'd', 'e', 'f', 'g', 'h'};
  // a full middle segment: ccs=0, t=0, n=0, c=0
  EXPECT_EQ(bytes(encodeSdoDownloadSegment(10, false, text, 7, false)),
            (std::vector<uint8_t>{0x00, 'a', 'b', 'c', 'd', 'e', 'f', 'g'}));
  // the last segment with 4 bytes: t=1, n=3, c=1 -> 0x10 | 3<<1 | 1 = 0x17, unused bytes 0
  EXPECT_EQ(bytes(encodeSdoDownloadSegment(10, true, text, 4, true)),
            (std::vector<uint8_t>{0x17, 'a', 'b', 'c', 'd', 0, 0, 0}));
  // an empty last segment: n=7, c=1 -> 0x0F
  EXPECT_EQ(bytes(encodeSdoDownloadSegment(10, false, text, 0, true)), (std::vector<uint8_t>{0x0F, 0, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(bytes(encodeSdoAbort(10, 0x1008, 0, sdo_abort::kToggleBit)),
            (std::vector<uint8_t>{0x80, 0x08, 0x10, 0, 0x00, 0x00, 0x03, 0x05}));
}

TEST(SdoSegmented, DecodesServerResponses) {
  // upload segment: scs=0, t=1, n=2, c=1 -> 0x10 | 2<<1 | 1 = 0x15: 5 data bytes
  auto r = decodeSdoResponse(sdoReply(10, {0x15, 'h', 'e', 'l', 'l', 'o', 0xAA, 0xAA}));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->kind, SdoResponse::Kind::kUploadSegment);
  EXPECT_TRUE(r->toggle);
  EXPECT_TRUE(r->last);
  EXPECT_EQ(r->size, 5);
  EXPECT_EQ(std::string(r->data.begin(), r->data.begin() + r->size), "hello");
  EXPECT_EQ(r->data[5], 0) << "bytes beyond n are not data";
  r = decodeSdoResponse(sdoReply(10, {0x00, 1, 2, 3, 4, 5, 6, 7}));
  ASSERT_TRUE(r);
  EXPECT_FALSE(r->toggle);
  EXPECT_FALSE(r->last);
  EXPECT_EQ(r->size, 7);
  // download segment acknowledged: scs=1, t -> 0x20 / 0x30
  r = decodeSdoResponse(sdoReply(10, {0x30, 0, 0, 0, 0, 0, 0, 0}));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->kind, SdoResponse::Kind::kDownloadSegmentAck);
  EXPECT_TRUE(r->toggle);
  r = decodeSdoResponse(sdoReply(10, {0x20, 0, 0, 0, 0, 0, 0, 0}));
  ASSERT_TRUE(r);
  EXPECT_FALSE(r->toggle);
  EXPECT_FALSE(decodeSdoResponse(sdoReply(10, {0x21, 0, 0, 0, 0, 0, 0, 0}))) << "reserved bits of a segment ack";
  // segmented upload initiated without size: 0x40
  r = decodeSdoResponse(sdoReply(10, {0x40, 0x08, 0x10, 0, 0, 0, 0, 0}));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->kind, SdoResponse::Kind::kUploadSegmented);
  EXPECT_FALSE(r->size_indicated);
  EXPECT_FALSE(decodeSdoResponse(sdoReply(10, {0x45, 0x08, 0x10, 0, 0, 0, 0, 0}))) << "n set while e = 0";
}

// A scripted CANopen node (the other end of the bus) for RemoteNode.
class ScriptedNode {
 public:
  ScriptedNode(uint16_t port, uint8_t node) : node_(node) {
    bus_ = std::make_shared<transport::UdpCanBus>("udp", "127.0.0.1", port);
    ch_ = bus_->open({});
    thread_ = std::thread([this] {
      CanFrame f;
      while (running_) {
        if (!ch_->receive(f, 0.02)) continue;
        if (f.id == 0x600u + node_) answerSdo(f);
        if (f.rtr && f.id == 0x180u + node_) ch_->send(CanFrame::make(0x180 + node_, {1, 2, 3, 4}));
        if (f.id == 0x000) nmt_seen_ = f.data[0];
      }
    });
  }
  ~ScriptedNode() {
    running_ = false;
    thread_.join();
  }
  void send(const CanFrame& f) { ch_->send(f); }
  std::atomic<int> nmt_seen_{-1};
  std::atomic<uint32_t> written_{0};
  std::atomic<uint32_t> abort_seen_{0};
  std::atomic<uint32_t> announced_{0};
  std::string downloaded() {
    std::lock_guard<std::mutex> lk(mutex_);
    return downloaded_;
  }
  std::mutex mutex_;
  std::string downloaded_;

 private:
  void answerSdo(const CanFrame& f) {
    const uint8_t ccs = f.data[0] >> 5;
    if (ccs == 4) {  // the master aborted
      abort_seen_ = f.data[4] | (f.data[5] << 8) | (f.data[6] << 16) | (static_cast<uint32_t>(f.data[7]) << 24);
      return;
    }
    if (ccs == 3) {  // upload segment request
      if (segmented_index_ == 0x5003) return;  // silent after the initiate: the master times out
      const bool t = f.data[0] & 0x10;
      const std::size_t len = std::min<std::size_t>(7, upload_.size() - at_);
      const bool last = at_ + len == upload_.size();
      const bool sent_toggle = segmented_index_ == 0x5002 ? false : t;  // 0x5002 never alternates
      CanFrame r = CanFrame::make(0x580 + node_, {0, 0, 0, 0, 0, 0, 0, 0});
      r.data[0] = static_cast<uint8_t>((sent_toggle ? 0x10 : 0) | ((7 - len) << 1) | (last ? 1 : 0));
      for (std::size_t i = 0; i < len; ++i) r.data[1 + i] = static_cast<uint8_t>(upload_[at_ + i]);
      at_ += len;
      ch_->send(r);
      return;
    }
    if (ccs == 0) {  // download segment
      const std::size_t len = 7 - ((f.data[0] >> 1) & 7);
      {
        std::lock_guard<std::mutex> lk(mutex_);
        downloaded_.append(reinterpret_cast<const char*>(f.data.data() + 1), len);
      }
      ch_->send(CanFrame::make(0x580 + node_, {static_cast<uint8_t>(0x20 | (f.data[0] & 0x10)), 0, 0, 0, 0, 0, 0, 0}));
      return;
    }
    const uint16_t index = static_cast<uint16_t>(f.data[1] | (f.data[2] << 8));
    if (index >= 0x5000 && index <= 0x5003) {
      segmented_index_ = index;
      at_ = 0;
      if (index == 0x5001) {
        std::lock_guard<std::mutex> lk(mutex_);
        downloaded_.clear();
        announced_ = f.data[4] | (f.data[5] << 8);
        ch_->send(CanFrame::make(0x580 + node_, {0x60, f.data[1], f.data[2], f.data[3], 0, 0, 0, 0}));
      } else {
        ch_->send(CanFrame::make(0x580 + node_, {0x41, f.data[1], f.data[2], f.data[3],
                                                 static_cast<uint8_t>(upload_.size()), 0, 0, 0}));
      }
      return;
    }
    if (index == 0x3000) return;  // never answers: a timeout
    if (index == 0x2000 && f.data[0] == 0x40) {
      ch_->send(CanFrame::make(0x580 + node_, {0x4B, f.data[1], f.data[2], f.data[3], 0x34, 0x12, 0, 0}));
    } else if (index == 0x2000 && f.data[0] == 0x2B) {
      written_ = f.data[4] | (f.data[5] << 8);
      ch_->send(CanFrame::make(0x580 + node_, {0x60, f.data[1], f.data[2], f.data[3], 0, 0, 0, 0}));
    } else if (index == 0x4000) {
      ch_->send(CanFrame::make(0x580 + node_, {0x41, f.data[1], f.data[2], f.data[3], 100, 0, 0, 0}));
    } else {
      ch_->send(CanFrame::make(0x580 + node_, {0x80, f.data[1], f.data[2], f.data[3], 0x00, 0x00, 0x02, 0x06}));
    }
  }
  std::string upload_ = "robot_sim motor_board";  // 21 bytes: 3 full segments
  std::atomic<uint16_t> segmented_index_{0};
  std::size_t at_ = 0;
  uint8_t node_;
  std::shared_ptr<transport::UdpCanBus> bus_;
  std::shared_ptr<transport::CanChannel> ch_;
  std::atomic<bool> running_{true};
  std::thread thread_;
};

class RemoteNodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    bus_ = std::make_shared<transport::UdpCanBus>("udp", "127.0.0.1", 27055);
    node_ = std::make_unique<RemoteNode>(bus_, 5);
    scripted_ = std::make_unique<ScriptedNode>(27055, 5);
    std::this_thread::sleep_for(std::chrono::milliseconds(80));
  }
  std::shared_ptr<transport::UdpCanBus> bus_;
  std::unique_ptr<RemoteNode> node_;
  std::unique_ptr<ScriptedNode> scripted_;
};

TEST_F(RemoteNodeTest, SdoReadWriteAbortAndTimeout) {
  EXPECT_EQ(node_->sdoRead(0x2000, 0, 0.5), 0x1234u);
  node_->sdoWrite(0x2000, 0, 777, 2, 0.5);
  EXPECT_EQ(scripted_->written_.load(), 777u);
  try {
    node_->sdoRead(0x1234, 1, 0.5);
    FAIL() << "an abort must throw";
  } catch (const SdoError& e) {
    EXPECT_EQ(e.abortCode(), sdo_abort::kNoObject);
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
  EXPECT_EQ(node_->sdoAborts(), 1u);
  try {
    node_->sdoRead(0x3000, 0, 0.05);
    FAIL() << "a timeout must throw";
  } catch (const SdoError& e) {
    EXPECT_EQ(e.abortCode(), 0u);
    EXPECT_NE(std::string(e.what()).find("no answer"), std::string::npos) << e.what();
  }
  EXPECT_EQ(node_->sdoTimeouts(), 1u);
  EXPECT_THROW(node_->sdoRead(0x4000, 0, 0.5), SdoError) << "segmented transfers are reported, not misread";
}

TEST_F(RemoteNodeTest, SegmentedUploadAndDownload) {
  const auto name = node_->sdoUpload(0x5000, 0, 0.5);
  EXPECT_EQ(std::string(name.begin(), name.end()), "robot_sim motor_board");
  const std::string label = "a label of 18 byte";
  node_->sdoDownload(0x5001, 0, std::vector<uint8_t>(label.begin(), label.end()), 0.5);
  EXPECT_EQ(scripted_->announced_.load(), label.size()) << "initiate carries the size";
  EXPECT_EQ(scripted_->downloaded(), label);
  node_->sdoDownload(0x5001, 0, {}, 0.5);
  EXPECT_EQ(scripted_->downloaded(), "") << "an empty value: one empty last segment";
  EXPECT_THROW(node_->sdoRead(0x5000, 0, 0.5), SdoError) << "sdoRead takes values of up to 4 bytes only";
}

TEST_F(RemoteNodeTest, SegmentedToggleErrorAndTimeoutAbort) {
  try {
    node_->sdoUpload(0x5002, 0, 0.5);
    FAIL() << "a segment with the wrong toggle bit must abort the transfer";
  } catch (const SdoError& e) {
    EXPECT_EQ(e.abortCode(), sdo_abort::kToggleBit) << e.what();
  }
  for (int i = 0; i < 50 && scripted_->abort_seen_.load() == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(scripted_->abort_seen_.load(), sdo_abort::kToggleBit) << "the master sends the abort";
  scripted_->abort_seen_ = 0;
  try {
    node_->sdoUpload(0x5003, 0, 0.05);
    FAIL() << "a node silent during the segments must time out";
  } catch (const SdoError& e) {
    EXPECT_EQ(e.abortCode(), sdo_abort::kTimeout) << e.what();
  }
  for (int i = 0; i < 50 && scripted_->abort_seen_.load() == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(scripted_->abort_seen_.load(), sdo_abort::kTimeout);
}

TEST_F(RemoteNodeTest, NmtPdoRtrCallbacksAndBootUp) {
  ASSERT_TRUE(node_->nmt(NmtCommand::kStart));
  bool got = false;
  node_->onFrame(0x185, [&](const CanFrame& f) {
    if (f.dlc != 4) return false;
    got = f.data[3] == 4;
    return true;
  });
  ASSERT_TRUE(node_->requestPdo(0x185, 4));
  EXPECT_TRUE(node_->waitFor([&] { return got; }, 1.0));
  EXPECT_EQ(scripted_->nmt_seen_.load(), 0x01);

  // Heartbeat consumption: the node's own NMT state and the age of its last heartbeat.
  EXPECT_EQ(node_->heartbeatState(), NmtState::kUnknown);
  EXPECT_LT(node_->heartbeatAge(), 0.0) << "no heartbeat yet";
  scripted_->send(CanFrame::make(0x705, {0x7F}));
  EXPECT_TRUE(node_->waitFor([&] { return node_->heartbeatState() == NmtState::kPreOperational; }, 1.0));
  EXPECT_GE(node_->heartbeatAge(), 0.0);
  EXPECT_LT(node_->heartbeatAge(), 0.5);

  int boots = 0;
  node_->onBootUp([&] { ++boots; });
  scripted_->send(CanFrame::make(0x705, {0x00}));
  EXPECT_TRUE(node_->waitFor([&] { return boots == 1; }, 1.0));
  EXPECT_EQ(node_->bootUps(), 1u);
  EXPECT_EQ(node_->state(), NmtState::kBootUp);
  scripted_->send(CanFrame::make(0x705, {0x05}));
  EXPECT_TRUE(node_->waitFor([&] { return node_->state() == NmtState::kOperational; }, 1.0));

  // Malformed: a registered PDO of the wrong length, a bad heartbeat, a bad SDO answer.
  scripted_->send(CanFrame::make(0x185, {1, 2}));
  scripted_->send(CanFrame::make(0x705, {0x42}));
  scripted_->send(CanFrame::make(0x585, {0x60}));
  // Unknown: a TPDO4 nobody registered.
  scripted_->send(CanFrame::make(0x485, {1}));
  EXPECT_TRUE(node_->waitFor([&] { return node_->malformed() == 3 && node_->unknownCobIds() == 1; }, 1.0))
      << node_->malformed() << " malformed, " << node_->unknownCobIds() << " unknown";
  // Another node's frames never reach this node's channel.
  scripted_->send(CanFrame::make(0x186, {1, 2, 3, 4}));
  node_->waitFor([] { return false; }, 0.1);
  EXPECT_EQ(node_->unknownCobIds(), 1u);
}
