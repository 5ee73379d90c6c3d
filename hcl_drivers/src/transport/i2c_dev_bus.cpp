#include "hcl_drivers/transport/i2c_dev_bus.h"

#include <fcntl.h>
#include <linux/i2c-dev.h>
#include <linux/i2c.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <system_error>

namespace hcl_drivers {
namespace transport {

I2cDevBus::I2cDevBus(const std::string& path) : I2cBus(path) {
  fd_ = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
  if (fd_ < 0) throw std::system_error(errno, std::generic_category(), "cannot open I2C bus " + path);
  ::ioctl(fd_, I2C_RETRIES, 0);  // we retry ourselves, counted
}

I2cDevBus::~I2cDevBus() {
  if (fd_ >= 0) ::close(fd_);
}

I2cStatus I2cDevBus::statusFromErrno(int err) {
  switch (err) {
    case ENXIO:
    case EREMOTEIO:
      return I2cStatus::kNack;
    case ETIMEDOUT:
      return I2cStatus::kTimeout;
    default:
      return I2cStatus::kBusError;  // EIO, EAGAIN (arbitration lost), EPROTO, ...
  }
}

I2cStatus I2cDevBus::transferOnce(std::vector<I2cMessage>& msgs, std::string& detail) {
  // The adapter's timeout is in units of 10 ms (I2C_TIMEOUT).
  ::ioctl(fd_, I2C_TIMEOUT, static_cast<unsigned long>(std::max(1.0, std::ceil(timeout() * 100.0))));
  std::vector<i2c_msg> raw(msgs.size());
  for (std::size_t i = 0; i < msgs.size(); ++i) {
    raw[i].addr = msgs[i].address;
    raw[i].flags = msgs[i].read ? I2C_M_RD : 0;
    raw[i].len = static_cast<__u16>(msgs[i].data.size());
    raw[i].buf = msgs[i].data.data();
  }
  i2c_rdwr_ioctl_data rdwr{raw.data(), static_cast<__u32>(raw.size())};
  if (::ioctl(fd_, I2C_RDWR, &rdwr) < 0) {
    const int err = errno;
    detail = std::strerror(err);
    return statusFromErrno(err);
  }
  return I2cStatus::kOk;
}

}  // namespace transport
}  // namespace hcl_drivers
