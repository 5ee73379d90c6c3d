// Before a simulator opens any channel: is one of them held by another simulation running now?
// Emulators remove what a previous run left behind (an I2C socket, a pty link) when they start
// and remove their own when they stop, so a simulator started on a running one's channels would
// cut that robot's boards off, even if it then failed on its next channel. The firmware host
// checks every configured channel first and refuses before it touches any.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <string>
#include <vector>

namespace robot_sim {

// Every reason the emulator blocks under `firmware` cannot have their channels now ("camera:
// TCP port 27230 is taken", "beacons: /tmp/.../beacons.tty is the pty of a running simulation");
// empty when all are free. Looks at the parameters `port` (a TCP port number, or a path), `bus`
// (sim://PATH) and `device`. A shared CAN bus is not judged: listening on it for another
// simulation's boards delayed this one's emulators past their drivers' first configuration.
std::vector<std::string> channelsInUse(XmlRpc::XmlRpcValue& firmware);

}  // namespace robot_sim
