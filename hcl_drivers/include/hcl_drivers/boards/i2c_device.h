// The I2C part of every I2C board's configuration, read the same way by each of them:
//   ~bus          /dev/i2c-N (robot) or sim:///PATH (emulator socket), required
//   ~address      7-bit address, within the part's range (YAML accepts 0x70), required
//   ~bus_timeout  [s] per attempt (default 0.02), ~bus_retries extra attempts (default 2, 0..10)
// Boards naming the same bus share one I2cBus (and belong on one loop group: `loop: i2c-1`).
#pragma once

#include <ros/ros.h>

#include <memory>

#include "hcl_drivers/transport/i2c_bus.h"

namespace hcl_drivers {

struct I2cDevice {
  std::shared_ptr<transport::I2cBus> bus;
  uint8_t address = 0;
};

// Throws ParameterError naming the parameter and the allowed values.
I2cDevice openI2cDevice(const ros::NodeHandle& pnh, int address_min, int address_max);

}  // namespace hcl_drivers
