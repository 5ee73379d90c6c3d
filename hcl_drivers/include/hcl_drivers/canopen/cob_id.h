// CANopen (CiA 301) predefined connection set: COB-ID = function code + node id (1..127).
#pragma once

#include <cstdint>

namespace hcl_drivers {
namespace canopen {

constexpr uint32_t kNmt = 0x000;
constexpr uint32_t kSync = 0x080;
constexpr uint32_t kEmcy = 0x080;        // + node
constexpr uint32_t kTpdo1 = 0x180;       // + node, node -> master
constexpr uint32_t kRpdo1 = 0x200;       // + node, master -> node
constexpr uint32_t kTpdo2 = 0x280;
constexpr uint32_t kRpdo2 = 0x300;
constexpr uint32_t kTpdo3 = 0x380;
constexpr uint32_t kRpdo3 = 0x400;
constexpr uint32_t kTpdo4 = 0x480;
constexpr uint32_t kRpdo4 = 0x500;
constexpr uint32_t kSdoTx = 0x580;       // + node, server (node) -> client (master)
constexpr uint32_t kSdoRx = 0x600;       // + node, client -> server
constexpr uint32_t kHeartbeat = 0x700;   // + node, boot-up and heartbeat

constexpr bool validNodeId(int id) { return id >= 1 && id <= 127; }
constexpr uint8_t nodeOf(uint32_t cob_id) { return static_cast<uint8_t>(cob_id & 0x7F); }
constexpr uint32_t functionOf(uint32_t cob_id) { return cob_id & 0x780; }

}  // namespace canopen
}  // namespace hcl_drivers
