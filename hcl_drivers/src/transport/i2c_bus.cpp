#include "hcl_drivers/transport/i2c_bus.h"

#include <sstream>
#include <stdexcept>

#include "hcl_drivers/transport/endpoint.h"
#include "hcl_drivers/transport/i2c_dev_bus.h"
#include "hcl_drivers/transport/sim_i2c_bus.h"

namespace hcl_drivers {
namespace transport {

const char* toString(I2cStatus s) {
  switch (s) {
    case I2cStatus::kOk: return "ok";
    case I2cStatus::kNack: return "NACK";
    case I2cStatus::kTimeout: return "timeout";
    case I2cStatus::kBusError: return "bus error";
  }
  return "?";
}

I2cStatus I2cBus::transfer(std::vector<I2cMessage>& msgs, std::string& error) {
  std::lock_guard<std::mutex> lk(bus_mutex_);
  I2cStatus st = I2cStatus::kBusError;
  std::string detail;
  const int attempts = 1 + retries_;
  for (int i = 0; i < attempts; ++i) {
    detail.clear();
    st = transferOnce(msgs, detail);
    std::lock_guard<std::mutex> counting(counters_mutex_);
    if (i > 0) ++counters_.retries;
    ++counters_.transactions;
    if (st == I2cStatus::kOk) return st;
    if (st == I2cStatus::kNack) ++counters_.nacks;
    if (st == I2cStatus::kTimeout) ++counters_.timeouts;
    if (st == I2cStatus::kBusError) ++counters_.bus_errors;
  }
  {
    std::lock_guard<std::mutex> counting(counters_mutex_);
    ++counters_.failed;
  }
  std::ostringstream os;
  os << "i2c 0x" << std::hex << static_cast<int>(msgs.empty() ? 0 : msgs[0].address) << std::dec << " on " << url_ << ": "
     << toString(st) << " after " << attempts << " attempt(s)";
  if (!detail.empty()) os << " (" << detail << ")";
  error = os.str();
  return st;
}

I2cStatus I2cBus::readRegisters(uint8_t address, uint8_t reg, std::size_t n, std::vector<uint8_t>& out,
                                std::string& error) {
  std::vector<I2cMessage> msgs(2);
  msgs[0].address = address;
  msgs[0].data = {reg};
  msgs[1].address = address;
  msgs[1].read = true;
  msgs[1].data.assign(n, 0);
  const I2cStatus st = transfer(msgs, error);
  if (st == I2cStatus::kOk) out = std::move(msgs[1].data);
  return st;
}

I2cStatus I2cBus::writeRegisters(uint8_t address, uint8_t reg, const std::vector<uint8_t>& values, std::string& error) {
  std::vector<I2cMessage> msgs(1);
  msgs[0].address = address;
  msgs[0].data.reserve(values.size() + 1);
  msgs[0].data.push_back(reg);
  msgs[0].data.insert(msgs[0].data.end(), values.begin(), values.end());
  return transfer(msgs, error);
}

std::unique_lock<std::mutex> I2cBus::lockAddress(uint8_t address) {
  std::mutex* m;
  {
    std::lock_guard<std::mutex> lk(address_map_mutex_);
    auto& slot = address_mutex_[address];
    if (!slot) slot = std::make_unique<std::mutex>();
    m = slot.get();
  }
  return std::unique_lock<std::mutex>(*m);
}

I2cCounters I2cBus::counters() const {
  std::lock_guard<std::mutex> lk(counters_mutex_);
  return counters_;
}

std::shared_ptr<I2cBus> openI2cBus(const std::string& url) {
  static std::mutex mutex;
  static std::map<std::string, std::weak_ptr<I2cBus>> buses;
  std::lock_guard<std::mutex> lk(mutex);
  if (auto existing = buses[url].lock()) return existing;
  const Endpoint ep = parseEndpoint(url);  // throws std::invalid_argument
  std::shared_ptr<I2cBus> bus;
  if (ep.scheme == "sim")
    bus = std::make_shared<SimI2cBus>(url, ep.path);
  else if (ep.scheme == "file" && ep.path.rfind("/dev/i2c", 0) == 0)
    bus = std::make_shared<I2cDevBus>(ep.path);
  else
    throw std::invalid_argument("bad I2C bus '" + url + "': expected /dev/i2c-N or sim:///PATH");
  buses[url] = bus;
  return bus;
}

}  // namespace transport
}  // namespace hcl_drivers
