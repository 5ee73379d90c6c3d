#include "hcl_drivers/boards/i2c_device.h"

#include <cstdio>
#include <stdexcept>
#include <system_error>

#include "hcl_drivers/board.h"

namespace hcl_drivers {

using robot_core::ParameterError;

I2cConfig I2cConfig::read(const robot_core::Params& p, int address_min, int address_max) {
  I2cConfig c;
  p.describe("bus", "the I2C bus: /dev/i2c-N (robot) or sim:///PATH (emulator socket)");
  c.bus = p.requireString("bus");
  c.bus_param = p.qualified("bus");
  char range[64];
  std::snprintf(range, sizeof(range), "0x%02x..0x%02x", address_min, address_max);
  p.describe("address", std::string("7-bit I2C address of the chip, ") + range + " (YAML accepts 0x70)");
  const int address = p.requireInt("address");
  if (address < address_min || address > address_max) {
    throw ParameterError("parameter " + p.qualified("address") + " = " + std::to_string(address) +
                         ": must be a 7-bit address in " + range);
  }
  c.address = static_cast<uint8_t>(address);
  p.describe("bus_timeout", "[s] time allowed for one I2C transfer attempt");
  c.timeout = p.optionalDouble("bus_timeout", 0.02);
  p.requireInRange("bus_timeout", c.timeout, 0.001, 1.0);
  p.describe("bus_retries", "extra attempts of a failed I2C transfer");
  c.retries = p.optionalInt("bus_retries", 2);
  p.requireInRange("bus_retries", c.retries, 0, 10);
  return c;
}

I2cDevice openI2cDevice(const I2cConfig& c) {
  I2cDevice d;
  d.address = c.address;
  try {
    d.bus = transport::openI2cBus(c.bus);
  } catch (const std::invalid_argument& e) {
    throw ParameterError("parameter " + c.bus_param + ": " + e.what());
  } catch (const std::system_error& e) {
    // a bus that cannot be opened is not a configuration error: the framework retries it
    throw std::runtime_error("I2C bus " + c.bus_param + " = '" + c.bus + "': " + e.what());
  }
  d.bus->setTimeout(c.timeout);
  d.bus->setRetries(c.retries);
  return d;
}

void diagnoseI2c(const I2cDevice& dev, diagnostic_updater::DiagnosticStatusWrapper& stat) {
  const auto c = dev.bus->counters();
  stat.addf("address", "0x%02x", dev.address);
  stat.add("bus", dev.bus->url());
  stat.add("bus NACKs", c.nacks);
  stat.add("bus timeouts", c.timeouts);
  stat.add("bus errors", c.bus_errors);
  stat.add("bus retries", c.retries);
}

bool checkI2cIdentity(const I2cConfig& config, uint8_t reg, std::size_t n, I2cDevice& dev, std::vector<uint8_t>& out,
                      CheckReport& report) {
  const std::string& url = config.bus;
  char address[8];
  std::snprintf(address, sizeof address, "0x%02x", static_cast<unsigned>(config.address));
  try {
    dev = openI2cDevice(config);
  } catch (const std::runtime_error& e) {  // ParameterError too: the doctor shows it as a row
    report.fail("bus", url, e.what(), "is the I2C adapter plugged in (ls /dev/i2c-*) and the path in the config right?");
    return false;
  }
  report.channel = {"i2c", url, dev.address, false};
  dev.bus->setRetries(0);
  std::string error;
  if (dev.bus->readRegisters(dev.address, reg, n, out, error) != transport::I2cStatus::kOk) {
    report.fail("address", std::string(address) + " ACKs on " + url, "no answer (" + error + ")",
                "is the chip powered and wired? A chip at another address is named below");
    return false;
  }
  report.channel.answered = true;
  report.ok("address", std::string(address) + " ACKs on " + url, "ACK");
  return true;
}

}  // namespace hcl_drivers
