// The emulators' blocks of a config (sim/firmware) read by each emulator's own reader
// (Firmware::configure), with no master, no world and no channel opened: check_sim_config runs it
// for check_config, and with --describe for the parameter tables (make docs).
#pragma once

#include <robot_core/params.h>

#include <functional>
#include <string>
#include <vector>

namespace robot_sim {

// A block FirmwareHost starts: a dictionary with a `type`, not `enabled: false`. Declares the
// host's two keys on the block.
bool isStartedEmulatorBlock(const robot_core::Params& block);

// "parameter <block>/type = 'X': unknown emulator type; allowed values: ..." (the registered ones).
std::string unknownEmulatorType(const robot_core::Params& block, const std::string& type);

// Each started block's errors, one line each: an unknown type (with the allowed ones), its
// emulator's reader refusing a value, a key that reader never asked for. `declared` is called
// for each good block with its type and what its reader declared.
std::vector<std::string> checkEmulatorBlocks(
    const robot_core::Params& firmware,
    const std::function<void(const std::string& type, const robot_core::Params& block)>& declared = {});

}  // namespace robot_sim
