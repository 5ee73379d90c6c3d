// The keys of a block its reader never asked for, one error line each, naming what reads the
// block and what it does read: "parameter /hcl/io/adress = 33: not a parameter of board type
// MCP23016 (it reads: address, bus, ...)". check_components and check_sim_config's emulators.
#pragma once

#include <sstream>
#include <string>
#include <vector>

#include "robot_core/params.h"

namespace robot_core {

// `reader`: "board type MCP23016", "emulator type MotorBoard"; call after the reader ran on `block`.
inline std::vector<std::string> unknownKeys(const Params& block, const std::string& reader) {
  std::ostringstream known;
  const std::vector<std::string> asked = block.askedKeys();
  for (std::size_t i = 0; i < asked.size(); ++i) known << (i ? ", " : "") << asked[i];
  std::vector<std::string> out;
  for (const std::string& line : block.unasked()) {
    const std::string name = line.substr(0, line.find(" = "));
    out.push_back("parameter " + name + line.substr(name.size()) + ": not a parameter of " + reader + " (it reads: " +
                  known.str() + ")");
  }
  return out;
}

}  // namespace robot_core
