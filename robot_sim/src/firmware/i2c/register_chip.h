// The common shape of an emulated I2C chip: a register pointer set by the first byte of a
// write, auto-incremented by every byte read or written after it. Chips override the
// register accessors (and nextPointer() when the pointer does not simply increment).
// Also reads the common parameters (bus, address: readBus) and attaches to the bus (attachBus).
#pragma once

#include <ros/ros.h>

#include <memory>
#include <mutex>
#include <string>

#include "i2c_bus_server.h"
#include "robot_sim/firmware/firmware.h"

namespace robot_sim {

class RegisterChip : public Firmware, public I2cSlave {
 public:
  ~RegisterChip() override { detachBus(); }

  bool acknowledge() override { return !silent(); }

  // board_reset for a chip with a power-on state (it overrides resetToPowerOn()), board_silent
  // for every chip.
  bool applyFault(const std::string& kind, bool active) override {
    if (kind == "board_reset" && resettable()) {
      if (active) resetToPowerOn();
      return true;
    }
    return Firmware::applyFault(kind, active);
  }
  void i2cWrite(const uint8_t* data, std::size_t n) override {
    if (n == 0) return;
    pointer_ = data[0];
    for (std::size_t i = 1; i < n; ++i) {
      writeRegister(pointer_, data[i]);
      pointer_ = nextPointer(pointer_);
    }
  }
  void i2cRead(uint8_t* data, std::size_t n) override {
    countPoll();
    for (std::size_t i = 0; i < n; ++i) {
      data[i] = readRegister(pointer_, i == 0);
      pointer_ = nextPointer(pointer_);
    }
  }

 protected:
  virtual uint8_t readRegister(uint8_t reg, bool first_of_read) = 0;
  virtual void writeRegister(uint8_t reg, uint8_t value) = 0;
  virtual uint8_t nextPointer(uint8_t reg) { return static_cast<uint8_t>(reg + 1); }
  // A chip that loses its registers on a reset (brown-out) puts them back to their power-on
  // values here, under its own lock.
  virtual bool resettable() const { return false; }
  virtual void resetToPowerOn() {}

  // Reads bus and address (the chip's 7-bit addresses: lo..hi), in configure().
  void readBus(const robot_core::Params& params, int lo, int hi) {
    params.describe("bus", "the simulated I2C bus the chip hangs on: sim:///PATH (the driver's bus in simulation)");
    bus_url_ = params.requireString("bus");
    simBusPath(bus_url_, params.qualified("bus"));  // the form only: nothing is opened here
    params.describe("address", "the chip's 7-bit address, as the driver's block says");
    const int address = params.requireInt("address");
    params.requireInRange("address", address, lo, hi);
    address_ = static_cast<uint8_t>(address);
  }
  // Attaches to the bus readBus() read, in start(). Throws std::runtime_error.
  void attachBus(FirmwareContext& ctx) {
    bus_ = I2cBusServer::attach(simBusPath(bus_url_, ctx.params.qualified("bus")), address_, this);
  }
  void detachBus() {
    if (bus_) bus_->detach(address_);
    bus_.reset();
  }

  uint8_t pointer_ = 0;
  uint8_t address_ = 0;
  std::string bus_url_;

 private:
  std::shared_ptr<I2cBusServer> bus_;
};

}  // namespace robot_sim
