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

#include <robot_core/params.h>

#include "hal_nodes/device.h"

namespace hal_nodes {

struct ContactSpec {
  std::string topic, input;
  int bit = -1;
  bool invert = false;

  // Reads <block>/{topic, input|bit, invert} of a device's parameters (from its configure());
  // throws ParameterError.
  static ContactSpec read(const robot_core::Params& params, const std::string& block) {
    const robot_core::Params p = params.block(block);
    ContactSpec c;
    p.describe("topic", "the board's inputs topic (hcl_drivers/DigitalInputs, /hcl/<board>/inputs)");
    c.topic = p.requireString("topic");
    p.describe("input", "the board's input name (give this or bit)");
    c.input = p.optionalString("input", "");
    p.describe("bit", "the input's bit number 0..31 (give this or input)");
    c.bit = p.optionalInt("bit", -1);
    if (c.input.empty() == (c.bit < 0))
      throw robot_core::ParameterError("parameter " + p.qualified("input") + " / " + p.qualified("bit") +
                                       ": give exactly one (the input's name, or its bit 0..31)");
    if (c.bit > 31)
      throw robot_core::ParameterError("parameter " + p.qualified("bit") + " = " + std::to_string(c.bit) +
                                       ": must be 0..31");
    p.describe("invert", "true for a normally-closed switch");
    c.invert = p.optionalBool("invert", false);
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
