// Emulator of the CAN motor board firmware (2 H-bridges, 2 encoders), from the board's
// protocol documentation (hcl_drivers/src/boards/can/motor_board_protocol.h describes the same):
//   RPDO1 0x200+n [pwm0 i16, pwm1 i16] 1/1000 duty    TPDO1 0x180+n [enc0 u32, enc1 u32]
//   TPDO2 0x280+n [pwm0 i16, pwm1 i16, flags u8 (bit0 watchdog stopped)]
//   SDO 0x2001:00 u16 watchdog ms (rw, 10..1000, default 200), 0x2002:00 u16 firmware version
// The watchdog: no RPDO1 for `watchdog` ms -> both motors 0 and flag set until the next RPDO1.
// After a reset the encoder counters restart at 0.
// Parameters: robot_sim/PARAMETERS.md (MotorBoard).
#include "canopen_firmware.h"
#include "robot_sim/firmware/firmware_registry.h"

namespace robot_sim {

class CanMotorBoardFirmware : public CanopenFirmware {
 protected:
  void readBoardParams(const robot_core::Params& params) override {
    params.describe("motors", "the world's motors driven by channel 0 and 1 (1 or 2 names)");
    motors_ = params.optionalStringList("motors");
    if (motors_.empty() || motors_.size() > 2) params.check("motors", "1..2 world motor names");
    params.describe("encoders", "the world's encoders counted by channel 0 and 1 (default: the motors')");
    encoders_ = params.optionalStringList("encoders", motors_);
    motors_.resize(2);
    encoders_.resize(2);
  }

  void setupBoard() override {
    addObject(0x2001, 0, {2, [this] { return static_cast<uint32_t>(watchdog_ms_); }, [this](uint32_t v) {
                            if (v < 10 || v > 1000) return false;
                            watchdog_ms_ = static_cast<uint16_t>(v);
                            return true;
                          }});
    addObject(0x2002, 0, {2, [] { return 0x0103u; }, nullptr});  // firmware 1.3
  }

  void resetBoard() override {
    pwm_ = {0, 0};
    watchdog_ms_ = 200;
    watchdog_stopped_ = false;
    last_command_ = now();
    for (int i = 0; i < 2; ++i) {
      offset_[i] = encoders_[i].empty() ? 0 : world().encoderTicks(encoders_[i]);
      if (!motors_[i].empty()) world().setMotorCommand(motors_[i], 0.0);
    }
  }

  RxResult onRpdo(const CanFrame& f) override {
    if (f.id != 0x200u + nodeId()) return RxResult::kUnknown;
    if (f.dlc != 4) return RxResult::kMalformed;
    for (int i = 0; i < 2; ++i) {
      const int v = static_cast<int16_t>(get16(f, 2 * i));
      pwm_[i] = static_cast<int16_t>(std::max(-1000, std::min(1000, v)));
    }
    last_command_ = now();
    watchdog_stopped_ = false;
    apply();
    return RxResult::kOk;
  }

  bool onRtr(uint32_t cob, CanFrame& out) override {
    if (cob == 0x180u + nodeId()) {
      out = CanFrame::make(cob, {0, 0, 0, 0, 0, 0, 0, 0});
      for (int i = 0; i < 2; ++i) put32(out, 4 * i, counter(i));
      return true;
    }
    if (cob == 0x280u + nodeId()) {
      out = CanFrame::make(cob, {0, 0, 0, 0, static_cast<uint8_t>(watchdog_stopped_ ? 1 : 0)});
      put16(out, 0, static_cast<uint16_t>(pwm_[0]));
      put16(out, 2, static_cast<uint16_t>(pwm_[1]));
      return true;
    }
    return false;
  }

  void tick(double t) override {
    if (!watchdog_stopped_ && t - last_command_ > watchdog_ms_ / 1000.0) {
      if (pwm_[0] != 0 || pwm_[1] != 0) ROS_WARN("%s firmware: no command for %u ms: motors stopped", name_.c_str(), watchdog_ms_);
      watchdog_stopped_ = true;
      pwm_ = {0, 0};
    }
    apply();
  }

  void truth(CanFirmware& m) override {
    // command_age: since the last command frame (RPDO1) the board received [s, its clock]: what
    // the watchdog watches, so a test can tell from the bus side that no motor ran blind.
    m.names = {"pwm0", "pwm1", "encoder0", "encoder1", "watchdog_stopped", "watchdog_ms", "command_age"};
    m.values = {double(pwm_[0]), double(pwm_[1]), double(counter(0)), double(counter(1)), watchdog_stopped_ ? 1.0 : 0.0,
                double(watchdog_ms_), now() - last_command_};
  }

 private:
  uint32_t counter(int i) {
    if (encoders_[i].empty()) return 0;
    return static_cast<uint32_t>(static_cast<uint64_t>(world().encoderTicks(encoders_[i]) - offset_[i]));
  }
  void apply() {
    for (int i = 0; i < 2; ++i)
      if (!motors_[i].empty()) world().setMotorCommand(motors_[i], pwm_[i] / 1000.0);
  }

  std::vector<std::string> motors_, encoders_;
  std::array<int16_t, 2> pwm_{0, 0};
  std::array<int64_t, 2> offset_{0, 0};
  uint16_t watchdog_ms_ = 200;
  bool watchdog_stopped_ = false;
  double last_command_ = 0.0;
};

ROBOT_SIM_REGISTER_FIRMWARE("MotorBoard", CanMotorBoardFirmware);

}  // namespace robot_sim
