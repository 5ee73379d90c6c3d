// Maxon EPOS (CANopen DS-402 drive) with the PDO mapping configured on our robot:
//   RPDO1  command_cob_id  (0x200+n), 6 bytes: controlword u16 (0x6040), target velocity i32 (0x60FF) [rpm]
//   TPDO1  status_cob_id   (0x180+n), 5 bytes: statusword u16 (0x6041), mode display i8 (0x6061),
//          error code u16 (0x603F)                                                           (RTR)
//   TPDO2  feedback_cob_id (0x280+n by default, EPOS firmware maps it elsewhere on some robots:
//          set it in config), 8 bytes: position actual i32 (0x6064) [qc], velocity actual i32 (0x606C) [rpm] (RTR)
//   SDO    0x6060:00 i8 modes of operation, written 3 (profile velocity) at configuration.
// Drive state machine (DS-402): switch-on-disabled -(0x06)-> ready-to-switch-on -(0x07)-> switched-on
// -(0x0F)-> operation-enabled; 0x06 disables; 0x80 resets a fault (only on request, never automatically).
#pragma once

#include <optional>
#include <string>

#include "hcl_drivers/canopen/pdo.h"

namespace hcl_drivers {
namespace epos {

using canopen::CanFrame;
constexpr uint16_t kModesOfOperation = 0x6060;
constexpr int8_t kProfileVelocityMode = 3;
constexpr uint16_t kCwShutdown = 0x0006, kCwSwitchOn = 0x0007, kCwEnableOperation = 0x000F, kCwFaultReset = 0x0080,
                   kCwDisableVoltage = 0x0000;

enum class DriveState { kNotReady, kSwitchOnDisabled, kReadyToSwitchOn, kSwitchedOn, kOperationEnabled, kQuickStop,
                        kFaultReaction, kFault };

inline DriveState decodeDriveState(uint16_t sw) {
  if ((sw & 0x4F) == 0x00) return DriveState::kNotReady;
  if ((sw & 0x4F) == 0x40) return DriveState::kSwitchOnDisabled;
  if ((sw & 0x6F) == 0x21) return DriveState::kReadyToSwitchOn;
  if ((sw & 0x6F) == 0x23) return DriveState::kSwitchedOn;
  if ((sw & 0x6F) == 0x27) return DriveState::kOperationEnabled;
  if ((sw & 0x6F) == 0x07) return DriveState::kQuickStop;
  if ((sw & 0x4F) == 0x0F) return DriveState::kFaultReaction;
  if ((sw & 0x4F) == 0x08) return DriveState::kFault;
  return DriveState::kNotReady;
}

inline const char* toString(DriveState s) {
  switch (s) {
    case DriveState::kNotReady: return "not-ready";
    case DriveState::kSwitchOnDisabled: return "switch-on-disabled";
    case DriveState::kReadyToSwitchOn: return "ready-to-switch-on";
    case DriveState::kSwitchedOn: return "switched-on";
    case DriveState::kOperationEnabled: return "operation-enabled";
    case DriveState::kQuickStop: return "quick-stop";
    case DriveState::kFaultReaction: return "fault-reaction";
    case DriveState::kFault: return "fault";
  }
  return "not-ready";
}

// The controlword that moves the drive one step towards `enable` (or keeps it there).
// A fault is never reset here: that is an explicit request (kCwFaultReset).
inline uint16_t nextControlword(DriveState s, bool enable) {
  if (!enable) return kCwShutdown;
  switch (s) {
    case DriveState::kSwitchOnDisabled: return kCwShutdown;
    case DriveState::kReadyToSwitchOn: return kCwSwitchOn;
    case DriveState::kSwitchedOn:
    case DriveState::kOperationEnabled: return kCwEnableOperation;
    case DriveState::kFault:
    case DriveState::kFaultReaction: return kCwDisableVoltage;
    default: return kCwShutdown;
  }
}

inline CanFrame encodeCommand(uint32_t cob_id, uint16_t controlword, int32_t target_rpm) {
  std::vector<uint8_t> b;
  canopen::putU16(b, controlword);
  canopen::putU32(b, static_cast<uint32_t>(target_rpm));
  return canopen::encodePdo(cob_id, b);
}

struct Status {
  uint16_t statusword = 0;
  int8_t mode_display = 0;
  uint16_t error_code = 0;
};
inline std::optional<Status> decodeStatus(const CanFrame& f) {
  if (f.rtr || f.error || f.dlc != 5) return std::nullopt;
  return Status{canopen::getU16(f, 0), static_cast<int8_t>(f.data[2]), canopen::getU16(f, 3)};
}

struct Feedback {
  int32_t position = 0;
  int32_t velocity_rpm = 0;
};
inline std::optional<Feedback> decodeFeedback(const CanFrame& f) {
  if (f.rtr || f.error || f.dlc != 8) return std::nullopt;
  return Feedback{canopen::getI32(f, 0), canopen::getI32(f, 4)};
}

}  // namespace epos
}  // namespace hcl_drivers
