// The I2C part of every I2C board's configuration (~bus, ~address, ~bus_timeout, ~bus_retries),
// read the same way by each of them: read and described in I2cConfig::read() (the table:
// hcl_drivers/PARAMETERS.md, make docs).
// Boards naming the same bus share one I2cBus (and belong on one loop group: `loop: i2c-1`).
#pragma once

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <ros/ros.h>

#include <memory>
#include <string>
#include <vector>

#include <robot_core/params.h>

#include "hcl_drivers/board_check.h"

#include "hcl_drivers/transport/i2c_bus.h"

namespace hcl_drivers {

struct I2cDevice {
  std::shared_ptr<transport::I2cBus> bus;
  uint8_t address = 0;
};

// The I2C parameters, read by the board's configure().
struct I2cConfig {
  std::string bus;        // URL
  std::string bus_param;  // "/hcl/<board>/bus", for messages
  uint8_t address = 0;
  double timeout = 0.02;
  int retries = 2;

  // Throws ParameterError naming the parameter and the allowed values.
  static I2cConfig read(const robot_core::Params& params, int address_min, int address_max);
};

// Opens (or shares) the bus: ParameterError for a URL no transport knows, std::runtime_error for
// a bus that cannot be opened now (the framework tries again).
I2cDevice openI2cDevice(const I2cConfig& config);

// The diagnostics every I2C board reports first: its address, its bus and the bus's error
// counters (shared by the boards on that bus).
void diagnoseI2c(const I2cDevice& dev, diagnostic_updater::DiagnosticStatusWrapper& stat);

// The hardware doctor's part every I2C board shares: opens the device as above (no retries:
// a chip that is there ACKs at once), declares the channel for the bus scan and reads `n` bytes
// from register `reg` (the chip's identity registers) into `out`. False, with a FAIL row, when
// the bus cannot be opened or the address does not ACK.
bool checkI2cIdentity(const I2cConfig& config, uint8_t reg, std::size_t n, I2cDevice& dev, std::vector<uint8_t>& out,
                      CheckReport& report);

}  // namespace hcl_drivers
