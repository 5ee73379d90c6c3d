// The simulation I2C master: the same combined transactions, carried to the firmware
// emulators over a Unix SOCK_SEQPACKET socket (one packet per transaction each way).
// Wire format (all integers little-endian), documented in sim_i2c_protocol.h.
#pragma once

#include <cstdint>

#include "hcl_drivers/transport/i2c_bus.h"

namespace hcl_drivers {
namespace transport {

class SimI2cBus : public I2cBus {
 public:
  // `url` is sim:///PATH; connects lazily, reconnects after the emulator restarts.
  SimI2cBus(const std::string& url, const std::string& socket_path);
  ~SimI2cBus() override;

 protected:
  I2cStatus transferOnce(std::vector<I2cMessage>& msgs, std::string& detail) override;

 private:
  bool connect(std::string& detail);
  void disconnect();
  std::string path_;
  int fd_ = -1;
  uint16_t seq_ = 0;
};

}  // namespace transport
}  // namespace hcl_drivers
