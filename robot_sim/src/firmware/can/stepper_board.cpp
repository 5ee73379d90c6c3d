// Emulator of the CAN stepper board firmware (2 steppers, min/max end switches):
//   RPDO1 0x200+n [target0 i32, target1 i32]   TPDO1 0x180+n [position0 i32, position1 i32]
//   TPDO2 0x280+n [end switches u8 (bit 2i min, 2i+1 max), moving u8 (bit i)]
// A stepper moving towards an end switch that is closed stops there (target := position).
// Parameters: robot_sim/PARAMETERS.md (StepperBoard).
#include "canopen_firmware.h"
#include "robot_sim/firmware/firmware_registry.h"

namespace robot_sim {

class CanStepperBoardFirmware : public CanopenFirmware {
 protected:
  void readBoardParams(const robot_core::Params& params) override {
    params.describe("steppers", "the world's steppers driven by channel 0 and 1 (1 or 2 names)");
    steppers_ = params.optionalStringList("steppers");
    if (steppers_.empty() || steppers_.size() > 2) params.check("steppers", "1..2 world stepper names");
    params.describe("end_switches", "the world's switches in bit order (min, max of each stepper; default "
                                    "<stepper>_min, <stepper>_max)");
    switches_ = params.optionalStringList("end_switches");
    if (!params.has("end_switches"))
      for (const auto& s : steppers_) {
        switches_.push_back(s + "_min");
        switches_.push_back(s + "_max");
      }
    steppers_.resize(2);
    switches_.resize(4);
  }

  void setupBoard() override {}

  void resetBoard() override {
    for (int i = 0; i < 2; ++i) {
      position_[i] = steppers_[i].empty() ? 0 : world().stepperPosition(steppers_[i]);
      target_[i] = position_[i];
      if (!steppers_[i].empty()) world().setStepperTarget(steppers_[i], target_[i]);
    }
  }

  RxResult onRpdo(const CanFrame& f) override {
    if (f.id != 0x200u + nodeId()) return RxResult::kUnknown;
    if (f.dlc != 8) return RxResult::kMalformed;
    for (int i = 0; i < 2; ++i) target_[i] = static_cast<int32_t>(get32(f, 4 * i));
    return RxResult::kOk;
  }

  bool onRtr(uint32_t cob, CanFrame& out) override {
    if (cob == 0x180u + nodeId()) {
      out = CanFrame::make(cob, {0, 0, 0, 0, 0, 0, 0, 0});
      put32(out, 0, static_cast<uint32_t>(position_[0]));
      put32(out, 4, static_cast<uint32_t>(position_[1]));
      return true;
    }
    if (cob == 0x280u + nodeId()) {
      out = CanFrame::make(cob, {endSwitches(), moving()});
      return true;
    }
    return false;
  }

  void tick(double) override {
    const uint8_t ends = endSwitches();
    for (int i = 0; i < 2; ++i) {
      if (steppers_[i].empty()) continue;
      position_[i] = static_cast<int32_t>(world().stepperPosition(steppers_[i]));
      const bool at_min = ends & (1 << (2 * i)), at_max = ends & (1 << (2 * i + 1));
      if ((target_[i] < position_[i] && at_min) || (target_[i] > position_[i] && at_max)) target_[i] = position_[i];
      world().setStepperTarget(steppers_[i], target_[i]);
    }
  }

  void truth(CanFirmware& m) override {
    m.names = {"position0", "position1", "target0", "target1", "end_switches"};
    m.values = {double(position_[0]), double(position_[1]), double(target_[0]), double(target_[1]), double(endSwitches())};
  }

 private:
  uint8_t endSwitches() const {
    uint8_t b = 0;
    for (int i = 0; i < 4; ++i)
      if (!switches_[i].empty() && world_ref().switchClosed(switches_[i])) b |= static_cast<uint8_t>(1 << i);
    return b;
  }
  uint8_t moving() const {
    uint8_t b = 0;
    for (int i = 0; i < 2; ++i)
      if (target_[i] != position_[i]) b |= static_cast<uint8_t>(1 << i);
    return b;
  }
  const World& world_ref() const { return const_cast<CanStepperBoardFirmware*>(this)->world(); }

  std::vector<std::string> steppers_, switches_;
  std::array<int32_t, 2> position_{0, 0}, target_{0, 0};
};

ROBOT_SIM_REGISTER_FIRMWARE("StepperBoard", CanStepperBoardFirmware);

}  // namespace robot_sim
