// The slave side of a simulated I2C bus (sim:///PATH): a Unix SOCK_SEQPACKET server that
// executes each request packet (one combined transaction, see the master's
// hcl_drivers/transport/sim_i2c_protocol.h) against the emulated chips attached at their
// addresses. Emulators naming the same path share one server, so one socket is one bus;
// one transaction at a time, like the wire. Written from the protocol text, not the master's code.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace robot_sim {

// An emulated I2C chip. Called with the bus locked, one message at a time.
class I2cSlave {
 public:
  virtual ~I2cSlave() = default;
  // false: the chip does not acknowledge its address (unpowered, silent fault) -> NACK.
  virtual bool acknowledge() = 0;
  // A write message (typically register pointer, then data bytes).
  virtual void i2cWrite(const uint8_t* data, std::size_t n) = 0;
  // A read message of n bytes.
  virtual void i2cRead(uint8_t* data, std::size_t n) = 0;
};

class I2cBusServer {
 public:
  // The bus at `path` (created on first use; a stale socket file is replaced) with `slave`
  // at 7-bit `address`. Throws std::runtime_error if the address is taken or the socket fails.
  static std::shared_ptr<I2cBusServer> attach(const std::string& path, uint8_t address, I2cSlave* slave);
  void detach(uint8_t address);

  explicit I2cBusServer(const std::string& path);
  ~I2cBusServer();
  I2cBusServer(const I2cBusServer&) = delete;
  I2cBusServer& operator=(const I2cBusServer&) = delete;

  unsigned long malformed() const { return malformed_; }

 private:
  void serve();
  std::vector<uint8_t> execute(const uint8_t* req, std::size_t n);

  std::string path_;
  int listen_fd_ = -1;
  std::mutex mutex_;  // guards slaves_: attach/detach vs transactions
  std::map<uint8_t, I2cSlave*> slaves_;
  std::atomic<bool> running_{true};
  std::atomic<unsigned long> malformed_{0};
  std::thread thread_;
};

// The path of a sim:///PATH bus parameter; throws std::runtime_error naming `param`.
std::string simBusPath(const std::string& url, const std::string& param);

}  // namespace robot_sim
