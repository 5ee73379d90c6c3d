// The simulated I2C master against a scripted slave on a real Unix SEQPACKET socket:
// combined transactions, NACK, timeout, bounded retries, late answers, emulator restart.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <functional>
#include <thread>

#include "hcl_drivers/transport/sim_i2c_bus.h"
#include "hcl_drivers/transport/sim_i2c_protocol.h"

using namespace hcl_drivers::transport;

namespace {

// A one-connection server answering each request packet with the packets `answer`
// returns (none = do not answer).
class ScriptedSlave {
 public:
  using Answer = std::function<std::vector<std::vector<uint8_t>>(const std::vector<uint8_t>&)>;
  ScriptedSlave(const std::string& path, Answer answer) : path_(path), answer_(std::move(answer)) {
    ::unlink(path.c_str());
    listen_fd_ = ::socket(AF_UNIX, SOCK_SEQPACKET, 0);
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    std::strncpy(a.sun_path, path.c_str(), sizeof(a.sun_path) - 1);
    EXPECT_EQ(::bind(listen_fd_, reinterpret_cast<sockaddr*>(&a), sizeof(a)), 0);
    EXPECT_EQ(::listen(listen_fd_, 4), 0);
    thread_ = std::thread([this] {
      const int c = ::accept(listen_fd_, nullptr, nullptr);
      if (c < 0) return;
      conn_ = c;
      uint8_t buf[4096];
      while (true) {
        const ssize_t n = ::recv(c, buf, sizeof(buf), 0);
        if (n <= 0) break;
        ++requests;
        for (const auto& out : answer_(std::vector<uint8_t>(buf, buf + n)))
          ::send(c, out.data(), out.size(), MSG_NOSIGNAL);
      }
    });
  }
  ~ScriptedSlave() {
    ::shutdown(listen_fd_, SHUT_RDWR);
    if (conn_ >= 0) ::shutdown(conn_, SHUT_RDWR);
    thread_.join();
    ::close(listen_fd_);
    if (conn_ >= 0) ::close(conn_);
    ::unlink(path_.c_str());
  }
  std::atomic<int> requests{0};

 private:
  std::string path_;
  Answer answer_;
  int listen_fd_ = -1;
  std::atomic<int> conn_{-1};
  std::thread thread_;
};

std::string tempPath(const char* tag) { return "/tmp/test_sim_i2c_" + std::string(tag) + "_" + std::to_string(::getpid()); }

std::vector<uint8_t> packet(const std::vector<uint8_t>& req, uint8_t status, std::vector<uint8_t> data) {
  data.insert(data.begin(), {'I', 'A', req[2], req[3], status});
  return data;
}
std::vector<std::vector<uint8_t>> answer(const std::vector<uint8_t>& req, uint8_t status, std::vector<uint8_t> data) {
  return {packet(req, status, std::move(data))};
}

}  // namespace

TEST(SimI2cProtocol, RequestCarriesEveryMessage) {
  std::vector<I2cMessage> m(2);
  m[0].address = 0x70;
  m[0].data = {0x00};
  m[1].address = 0x70;
  m[1].read = true;
  m[1].data.assign(4, 0);
  const auto p = sim_i2c::encodeRequest(0x1234, m);
  const std::vector<uint8_t> expect = {'I', 'Q', 0x34, 0x12, 2, 0x70, 0, 1, 0, 0x00, 0x70, 1, 4, 0};
  EXPECT_EQ(p, expect);
  const uint8_t a[] = {'I', 'A', 0x34, 0x12, 0, 9, 8};
  const auto d = sim_i2c::decodeAnswer(a, sizeof(a));
  ASSERT_TRUE(d);
  EXPECT_EQ(d->seq, 0x1234);
  EXPECT_EQ(d->read_bytes, (std::vector<uint8_t>{9, 8}));
  const uint8_t bad[] = {'I', 'A', 0, 0, 7};
  EXPECT_FALSE(sim_i2c::decodeAnswer(bad, sizeof(bad)));
}

TEST(SimI2cBus, CombinedReadReturnsTheSlavesBytes) {
  const auto path = tempPath("read");
  ScriptedSlave slave(path, [](const std::vector<uint8_t>& r) {
    EXPECT_EQ(r[4], 2);     // two messages
    EXPECT_EQ(r[5], 0x60);  // address
    EXPECT_EQ(r[9], 0x02);  // register pointer
    return answer(r, 0, {0x03, 0x84});
  });
  SimI2cBus bus("sim://" + path, path);
  std::vector<uint8_t> out;
  std::string err;
  ASSERT_EQ(bus.readRegisters(0x60, 0x02, 2, out, err), I2cStatus::kOk) << err;
  EXPECT_EQ(out, (std::vector<uint8_t>{0x03, 0x84}));
}

TEST(SimI2cBus, NackIsRetriedABoundedNumberOfTimesAndCounted) {
  const auto path = tempPath("nack");
  ScriptedSlave slave(path, [](const std::vector<uint8_t>& r) { return answer(r, 1, {}); });
  SimI2cBus bus("sim://" + path, path);
  bus.setRetries(3);
  std::string err;
  EXPECT_EQ(bus.writeRegisters(0x10, 0x02, {5}, err), I2cStatus::kNack);
  EXPECT_NE(err.find("NACK"), std::string::npos) << err;
  EXPECT_NE(err.find("0x10"), std::string::npos) << err;
  EXPECT_EQ(slave.requests.load(), 4);
  const auto c = bus.counters();
  EXPECT_EQ(c.nacks, 4u);
  EXPECT_EQ(c.retries, 3u);
  EXPECT_EQ(c.failed, 1u);
}

TEST(SimI2cBus, SilentSlaveTimesOutAndLateAnswersAreNotTakenForNewOnes) {
  const auto path = tempPath("late");
  std::atomic<int> n{0};
  std::vector<uint8_t> held;
  ScriptedSlave slave(path, [&](const std::vector<uint8_t>& r) -> std::vector<std::vector<uint8_t>> {
    if (n++ == 0) {  // first request: no answer now, answered late just before the second's
      held = packet(r, 0, {0xAA});
      return {};
    }
    return {held, packet(r, 0, {0x55})};
  });
  SimI2cBus bus("sim://" + path, path);
  bus.setRetries(0);
  bus.setTimeout(0.02);
  std::vector<uint8_t> out;
  std::string err;
  EXPECT_EQ(bus.readRegisters(0x20, 0, 1, out, err), I2cStatus::kTimeout);
  ASSERT_EQ(bus.readRegisters(0x20, 0, 1, out, err), I2cStatus::kOk) << err;
  EXPECT_EQ(out, (std::vector<uint8_t>{0x55}));
  EXPECT_EQ(bus.counters().timeouts, 1u);
}

TEST(SimI2cBus, NoEmulatorIsABusErrorAndReconnectsWhenItAppears) {
  const auto path = tempPath("late_start");
  SimI2cBus bus("sim://" + path, path);
  bus.setRetries(0);
  std::string err;
  EXPECT_EQ(bus.writeRegisters(0x10, 0, {1}, err), I2cStatus::kBusError);
  EXPECT_NE(err.find("no emulator"), std::string::npos) << err;
  ScriptedSlave slave(path, [](const std::vector<uint8_t>& r) { return answer(r, 0, {}); });
  EXPECT_EQ(bus.writeRegisters(0x10, 0, {1}, err), I2cStatus::kOk) << err;
}

TEST(SimI2cBus, WrongAnswerLengthIsABusError) {
  const auto path = tempPath("short");
  ScriptedSlave slave(path, [](const std::vector<uint8_t>& r) { return answer(r, 0, {1}); });
  SimI2cBus bus("sim://" + path, path);
  bus.setRetries(1);
  std::vector<uint8_t> out;
  std::string err;
  EXPECT_EQ(bus.readRegisters(0x20, 0, 2, out, err), I2cStatus::kBusError);
  EXPECT_EQ(bus.counters().bus_errors, 2u);
}
