// Emulators register themselves by type name (the `type` in config) at library load, with
// this line inside namespace robot_sim after the class:
//   ROBOT_SIM_REGISTER_FIRMWARE("ExampleBoard", ExampleBoardFirmware);
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "robot_sim/firmware/firmware.h"

namespace robot_sim {

class FirmwareRegistry {
 public:
  using Factory = std::function<std::unique_ptr<Firmware>()>;

  static FirmwareRegistry& instance();
  void add(const std::string& type, Factory factory);
  // Null when the type is unknown.
  std::unique_ptr<Firmware> create(const std::string& type) const;
  std::vector<std::string> types() const;

 private:
  std::map<std::string, Factory> factories_;
};

struct FirmwareRegistration {
  FirmwareRegistration(const std::string& type, FirmwareRegistry::Factory factory) {
    FirmwareRegistry::instance().add(type, std::move(factory));
  }
};

}  // namespace robot_sim

#define ROBOT_SIM_REGISTER_FIRMWARE(type_name, Class)                      \
  static const FirmwareRegistration robot_sim_registration_##Class( \
      type_name, [] { return std::unique_ptr<Firmware>(new Class()); })
