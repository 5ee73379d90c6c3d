// The Linux i2c-dev master (/dev/i2c-N): every transaction is one ioctl(I2C_RDWR), so the
// kernel issues repeated starts between its messages and nobody else gets the bus in between.
#pragma once

#include "hcl_drivers/transport/i2c_bus.h"

namespace hcl_drivers {
namespace transport {

class I2cDevBus : public I2cBus {
 public:
  // Opens the device; throws std::system_error naming the path.
  explicit I2cDevBus(const std::string& path);
  ~I2cDevBus() override;

  // errno of a failed ioctl(I2C_RDWR) -> status (ENXIO/EREMOTEIO: NACK, ETIMEDOUT: timeout).
  static I2cStatus statusFromErrno(int err);

 protected:
  I2cStatus transferOnce(std::vector<I2cMessage>& msgs, std::string& detail) override;

 private:
  int fd_ = -1;
};

}  // namespace transport
}  // namespace hcl_drivers
