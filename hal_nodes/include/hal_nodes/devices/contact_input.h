// One named switch on a board's hcl_drivers/DigitalInputs, configured as
//   {topic: /hcl/<board>/inputs, input: <the board's input name> | bit: 0..31, invert: false}
// Shared by the devices that read switches (human interface, hand end switches).
#pragma once

#include <hcl_drivers/DigitalInputs.h>

#include <algorithm>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "hal_nodes/device.h"

namespace hal_nodes {

struct ContactSpec {
  std::string topic, input;
  int bit = -1;
  bool invert = false;

  // Reads ~<block>/{topic, input|bit, invert}; throws ParameterError.
  static ContactSpec read(const ros::NodeHandle& pnh, const std::string& block) {
    ros::NodeHandle p(pnh, block);
    ContactSpec c;
    c.topic = robot_core::requireString(p, "topic");
    c.input = robot_core::optionalString(p, "input", "");
    c.bit = robot_core::optionalInt(p, "bit", -1);
    if (c.input.empty() == (c.bit < 0))
      throw robot_core::ParameterError("parameter " + robot_core::qualified(p, "input") + " / " +
                                       robot_core::qualified(p, "bit") +
                                       ": give exactly one (the input's name, or its bit 0..31)");
    if (c.bit > 31)
      throw robot_core::ParameterError("parameter " + robot_core::qualified(p, "bit") + " = " + std::to_string(c.bit) +
                                       ": must be 0..31");
    c.invert = robot_core::optionalBool(p, "invert", false);
    return c;
  }

  // Closed (after inversion), or nothing when the message does not carry the input.
  std::optional<bool> closed(const hcl_drivers::DigitalInputs& m) const {
    int b = bit;
    if (!input.empty()) {
      const auto it = std::find(m.names.begin(), m.names.end(), input);
      if (it == m.names.end()) return std::nullopt;
      b = static_cast<int>(it - m.names.begin());
    }
    return (((m.bits >> b) & 1u) != 0) != invert;
  }
};

}  // namespace hal_nodes
