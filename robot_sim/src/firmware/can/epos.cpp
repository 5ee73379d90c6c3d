// Emulator of a Maxon EPOS (CANopen DS-402 drive) with our robot's PDO mapping:
//   RPDO1 0x200+n [controlword u16, target velocity i32 rpm]
//   TPDO1 0x180+n [statusword u16, mode display i8, error code u16]
//   TPDO2 feedback_cob_id (default 0x280+n) [position actual i32 qc, velocity actual i32 rpm]
//   SDO 0x6060:00 i8 modes of operation (rw; 3 = profile velocity), 0x6061:00 display, 0x603F:00 error code
// DS-402 device control: shutdown (0x06), switch on (0x07), enable operation (0x0F), disable
// voltage (bit1 = 0), fault reset (bit 7 rising edge). The motor is driven (fraction = target /
// nominal_rpm) only in operation-enabled and profile velocity mode; a fault (injected:
// epos_fault) stops it and sets error code 0x3210 (overvoltage) until a fault reset.
// Parameters: robot_sim/PARAMETERS.md (Epos).
#include <cmath>

#include "canopen_firmware.h"
#include "robot_sim/firmware/firmware_registry.h"

namespace robot_sim {

class EposFirmware : public CanopenFirmware {
 protected:
  enum State : uint16_t { kSwitchOnDisabled = 0x0240, kReadyToSwitchOn = 0x0221, kSwitchedOn = 0x0233,
                          kOperationEnabled = 0x0237, kFault = 0x0208 };

  void readBoardParams(const robot_core::Params& params) override {
    params.describe("motor", "the world's motor the drive turns");
    motor_ = params.requireString("motor");
    params.describe("encoder", "the world's encoder of its position feedback (default: the motor's)");
    encoder_ = params.optionalString("encoder", motor_);
    params.describe("nominal_rpm", "[rpm] the target velocity that drives the motor at full command");
    nominal_rpm_ = params.optionalDouble("nominal_rpm", 8000.0);
    params.requirePositive("nominal_rpm", nominal_rpm_);
    params.describe("counts_per_rev", "[qc] position counts per motor revolution");
    counts_per_rev_ = params.optionalDouble("counts_per_rev", 2000.0);
    params.requirePositive("counts_per_rev", counts_per_rev_);
    params.describe("feedback_cob_id", "the COB-ID of TPDO2 (position and velocity), the driver's; default 0x280 + node_id");
    const int fb = params.optionalInt("feedback_cob_id", 0x280 + nodeId());
    params.requireInRange("feedback_cob_id", fb, 1, 0x7FF);
    feedback_cob_ = static_cast<uint32_t>(fb);
  }

  void setupBoard() override {
    if ((feedback_cob_ & 0x7F) != nodeId()) addExtraCobId(feedback_cob_);
    addObject(0x6060, 0, {1, [this] { return static_cast<uint32_t>(static_cast<uint8_t>(mode_)); }, [this](uint32_t v) {
                            mode_ = static_cast<int8_t>(v);
                            return true;
                          }});
    addObject(0x6061, 0, {1, [this] { return static_cast<uint32_t>(static_cast<uint8_t>(mode_)); }, nullptr});
    addObject(0x603F, 0, {2, [this] { return static_cast<uint32_t>(error_code_); }, nullptr});
  }

  void resetBoard() override {
    state_ = kSwitchOnDisabled;
    mode_ = 0;
    error_code_ = 0;
    target_rpm_ = 0;
    velocity_rpm_ = 0.0;
    last_cw_ = 0;
    offset_ = world().encoderTicks(encoder_);
    last_ticks_ = offset_;
    last_t_ = now();
    world().setMotorCommand(motor_, 0.0);
  }

  RxResult onRpdo(const CanFrame& f) override {
    if (f.id != 0x200u + nodeId()) return RxResult::kUnknown;
    if (f.dlc != 6) return RxResult::kMalformed;
    const uint16_t cw = get16(f, 0);
    target_rpm_ = static_cast<int32_t>(get32(f, 2));
    control(cw);
    return RxResult::kOk;
  }

  bool onRtr(uint32_t cob, CanFrame& out) override {
    if (cob == 0x180u + nodeId()) {
      out = CanFrame::make(cob, {0, 0, static_cast<uint8_t>(mode_), 0, 0});
      put16(out, 0, state_);
      put16(out, 3, error_code_);
      return true;
    }
    if (cob == feedback_cob_) {
      out = CanFrame::make(cob, {0, 0, 0, 0, 0, 0, 0, 0});
      put32(out, 0, static_cast<uint32_t>(static_cast<int32_t>(world().encoderTicks(encoder_) - offset_)));
      put32(out, 4, static_cast<uint32_t>(static_cast<int32_t>(std::lround(velocity_rpm_))));
      return true;
    }
    return false;
  }

  void tick(double t) override {
    const bool drive = state_ == kOperationEnabled && mode_ == 3;
    world().setMotorCommand(motor_, drive ? std::max(-1.0, std::min(1.0, target_rpm_ / nominal_rpm_)) : 0.0);
    const double dt = t - last_t_;
    if (dt >= 0.02) {  // velocity actual: 20 ms window, like the drive's averaged velocity
      const int64_t ticks = world().encoderTicks(encoder_);
      velocity_rpm_ = (ticks - last_ticks_) / counts_per_rev_ / dt * 60.0;
      last_ticks_ = ticks;
      last_t_ = t;
    }
  }

  bool boardFault(const std::string& kind, bool active) override {
    if (kind != "epos_fault") return false;
    std::lock_guard<std::mutex> lk(mutex());
    if (active) {
      state_ = kFault;
      error_code_ = 0x3210;
    }
    return true;
  }

  void truth(CanFirmware& m) override {
    m.names = {"statusword", "mode", "error_code", "target_rpm", "velocity_rpm", "driving"};
    m.values = {double(state_), double(mode_), double(error_code_), double(target_rpm_), velocity_rpm_,
                state_ == kOperationEnabled && mode_ == 3 && target_rpm_ != 0 ? 1.0 : 0.0};
  }

 private:
  void control(uint16_t cw) {
    const bool fault_reset_edge = (cw & 0x80) && !(last_cw_ & 0x80);
    last_cw_ = cw;
    if (state_ == kFault) {
      if (fault_reset_edge) {
        state_ = kSwitchOnDisabled;
        error_code_ = 0;
      }
      return;
    }
    if (!(cw & 0x02)) {  // disable voltage
      state_ = kSwitchOnDisabled;
      return;
    }
    const uint16_t c = cw & 0x0F;
    if (c == 0x06) {
      state_ = kReadyToSwitchOn;
    } else if (c == 0x07) {
      if (state_ == kReadyToSwitchOn || state_ == kOperationEnabled) state_ = kSwitchedOn;
    } else if (c == 0x0F) {
      if (state_ == kSwitchedOn || state_ == kOperationEnabled) state_ = kOperationEnabled;
    }
  }

  std::string motor_, encoder_;
  double nominal_rpm_ = 8000.0, counts_per_rev_ = 2000.0;
  uint32_t feedback_cob_ = 0;
  uint16_t state_ = kSwitchOnDisabled;
  int8_t mode_ = 0;
  uint16_t error_code_ = 0, last_cw_ = 0;
  int32_t target_rpm_ = 0;
  double velocity_rpm_ = 0.0, last_t_ = 0.0;
  int64_t offset_ = 0, last_ticks_ = 0;
};

ROBOT_SIM_REGISTER_FIRMWARE("Epos", EposFirmware);

}  // namespace robot_sim
