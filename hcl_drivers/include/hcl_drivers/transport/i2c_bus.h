// An I2C bus master: combined write/read transactions (what ioctl(I2C_RDWR) does), with
// bounded retries, per-address locking and error counters. Two implementations:
//   /dev/i2c-N        i2c_dev_bus.h  (Linux i2c-dev, the USB-I2C converter on the robot)
//   sim:///PATH       sim_i2c_bus.h  (a local socket to the firmware emulators)
// Boards on one bus in one process share one I2cBus object (openI2cBus), so their
// transactions never interleave and their errors add up in one place.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace hcl_drivers {
namespace transport {

// One message of a combined transaction: a write of `data`, or a read of data.size() bytes
// into `data`. Addresses are 7-bit.
struct I2cMessage {
  uint8_t address = 0;
  bool read = false;
  std::vector<uint8_t> data;
};

enum class I2cStatus { kOk, kNack, kTimeout, kBusError };
const char* toString(I2cStatus s);

struct I2cCounters {
  unsigned long transactions = 0;  // attempted (retries included)
  unsigned long nacks = 0;
  unsigned long timeouts = 0;
  unsigned long bus_errors = 0;
  unsigned long retries = 0;
  unsigned long failed = 0;        // transactions that failed after every retry
};

class I2cBus {
 public:
  virtual ~I2cBus() = default;

  // One combined transaction (repeated starts between messages, one stop at the end),
  // retried up to retries() more times on NACK, timeout or bus error. On failure `error`
  // says why (address, status, attempts).
  I2cStatus transfer(std::vector<I2cMessage>& msgs, std::string& error);

  // Register helpers on top of transfer(): the usual "write register pointer, then read"
  // (combined, so nobody can move the pointer in between) and "write pointer + data".
  I2cStatus readRegisters(uint8_t address, uint8_t reg, std::size_t n, std::vector<uint8_t>& out, std::string& error);
  I2cStatus writeRegisters(uint8_t address, uint8_t reg, const std::vector<uint8_t>& values, std::string& error);

  // Held by a board across several transactions that must not be interleaved with another
  // user of the same address (e.g. two driver instances configured on one device).
  std::unique_lock<std::mutex> lockAddress(uint8_t address);

  void setRetries(int retries) { retries_ = retries < 0 ? 0 : retries; }
  int retries() const { return retries_; }
  void setTimeout(double seconds) { timeout_s_ = seconds; }
  double timeout() const { return timeout_s_; }
  I2cCounters counters() const;
  const std::string& url() const { return url_; }

 protected:
  explicit I2cBus(std::string url) : url_(std::move(url)) {}
  // One attempt, called with the bus locked. `detail` gets the OS / emulator message.
  virtual I2cStatus transferOnce(std::vector<I2cMessage>& msgs, std::string& detail) = 0;

 private:
  std::string url_;
  int retries_ = 2;
  double timeout_s_ = 0.02;
  std::mutex bus_mutex_;               // one transaction on the wire at a time
  // Apart from bus_mutex_: diagnostics read the counters while a silent device holds the
  // bus in its timeouts, and must not wait for it (its neighbours' reports would stall).
  mutable std::mutex counters_mutex_;
  std::mutex address_map_mutex_;
  std::map<uint8_t, std::unique_ptr<std::mutex>> address_mutex_;
  I2cCounters counters_;
};

// The process-wide bus for `url` ("/dev/i2c-N" or "sim:///PATH"), created on first use.
// Throws std::invalid_argument for a URL that is neither, std::system_error when the
// device cannot be opened (a sim bus connects lazily: its emulator may start later).
std::shared_ptr<I2cBus> openI2cBus(const std::string& url);

}  // namespace transport
}  // namespace hcl_drivers
