// The hardware doctor's checks of a whole bus, after each board checked itself (board_check.h):
// what no single board can see. CAN: the interface (up, bitrate, error state), nodes nobody
// configured (a board at a wrong node id is named "found at N, expected M"), bus load and error
// frames over a window. I2C: chips at addresses nobody configured, named the same way.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <string>
#include <vector>

#include "hcl_drivers/board_check.h"

namespace hcl_drivers {
namespace doctor {

// `boards`: the reports of the boards on this bus (their rows get the "found at" finding).
// `computer`: the config's computer section (computer/can/<iface>/bitrate), may be invalid.
// `window`: seconds of listening for the load.
void checkCanBus(const std::string& url, const std::vector<CheckReport*>& boards, XmlRpc::XmlRpcValue& computer,
                 double window, std::vector<CheckRow>& rows);
void checkI2cBus(const std::string& url, const std::vector<CheckReport*>& boards, std::vector<CheckRow>& rows);

// For a board that did not answer at `expected`: the closest of the `found` unconfigured
// addresses (preferring one whose identity text names the board), or -1.
int pairMissing(const std::string& board, int expected, const std::vector<std::pair<int, std::string>>& found);

}  // namespace doctor
}  // namespace hcl_drivers
