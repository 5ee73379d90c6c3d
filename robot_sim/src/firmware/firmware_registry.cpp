#include "robot_sim/firmware/firmware_registry.h"

namespace robot_sim {

FirmwareRegistry& FirmwareRegistry::instance() {
  static FirmwareRegistry registry;
  return registry;
}

void FirmwareRegistry::add(const std::string& type, Factory factory) { factories_[type] = std::move(factory); }

std::unique_ptr<Firmware> FirmwareRegistry::create(const std::string& type) const {
  auto it = factories_.find(type);
  return it == factories_.end() ? nullptr : it->second();
}

std::vector<std::string> FirmwareRegistry::types() const {
  std::vector<std::string> out;
  for (const auto& kv : factories_) out.push_back(kv.first);
  return out;
}

}  // namespace robot_sim
