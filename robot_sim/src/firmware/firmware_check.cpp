#include "robot_sim/firmware/firmware_check.h"

#include <robot_core/unknown_keys.h>

#include <sstream>

#include "robot_sim/firmware/firmware_registry.h"

namespace robot_sim {

namespace {
std::string joined(const std::vector<std::string>& names) {
  std::ostringstream s;
  for (std::size_t i = 0; i < names.size(); ++i) s << (i ? ", " : "") << names[i];
  return s.str();
}
}  // namespace

bool isStartedEmulatorBlock(const robot_core::Params& block) {
  if (!block.has("type")) return false;  // not an emulator's block
  block.describe("enabled", "false: the simulator does not start this emulator (its settings stay for when it is enabled)");
  if (!block.optionalBool("enabled", true)) return false;
  block.describe("type", "the emulator type: the board type of its driver (a section of this table)");
  return true;
}

std::string unknownEmulatorType(const robot_core::Params& block, const std::string& type) {
  return "parameter " + block.qualified("type") + " = '" + type +
         "': unknown emulator type; allowed values: " + joined(FirmwareRegistry::instance().types());
}

std::vector<std::string> checkEmulatorBlocks(
    const robot_core::Params& firmware,
    const std::function<void(const std::string& type, const robot_core::Params& block)>& declared) {
  std::vector<std::string> errors;
  for (const std::string& key : firmware.keys()) {
    const robot_core::Params block = firmware[key];
    try {
      if (!isStartedEmulatorBlock(block)) continue;
      const std::string type = block.requireString("type");
      auto emulator = FirmwareRegistry::instance().create(type);
      if (!emulator) {
        errors.push_back(unknownEmulatorType(block, type));
        continue;
      }
      emulator->configure(block);
      const std::size_t before = errors.size();
      for (const std::string& line : robot_core::unknownKeys(block, "emulator type " + type)) errors.push_back(line);
      if (errors.size() == before && declared) declared(type, block);
    } catch (const std::exception& e) {
      errors.push_back(e.what());
    }
  }
  return errors;
}

}  // namespace robot_sim
