// Emulator of the CAN servo board firmware (4 RC servos, 4 ADC channels with SHARP GP2D12
// rangers, 16 switches):
//   RPDO1 0x200+n [pulse0..3 u16 us; 0 = off]   TPDO1 0x180+n [adc0..3 u16, 10 bit, 5 V ref]
//   TPDO2 0x280+n [switches u16]
// A servo at pulse p is driven to (p - 1500) / 500 * pi/2 rad. The ADC reads the GP2D12 output
// for the world's range (datasheet curve below, 10..80 cm; nearer the output falls again,
// farther it flattens to ~0.3 V) plus 1 LSB of noise.
// Parameters: robot_sim/PARAMETERS.md (ServoBoard).
#include <cmath>
#include <random>

#include "canopen_firmware.h"
#include "robot_sim/firmware/firmware_registry.h"

namespace robot_sim {

class CanServoBoardFirmware : public CanopenFirmware {
 protected:
  void readBoardParams(const robot_core::Params& params) override {
    params.describe("servos", "the world's servos on pulse outputs 0..3 (at most 4 names)");
    servos_ = params.optionalStringList("servos");
    if (servos_.size() > 4) params.check("servos", "at most 4 names");
    params.describe("rangers", "the world's SHARP rangers on ADC channels 0..3 (at most 4 names)");
    rangers_ = params.optionalStringList("rangers");
    if (rangers_.size() > 4) params.check("rangers", "at most 4 names");
    params.describe("switches", "the world's switches on input bits 0..15 (at most 16 names)");
    switches_ = params.optionalStringList("switches");
    if (switches_.size() > 16) params.check("switches", "at most 16 names");
    servos_.resize(4);
    rangers_.resize(4);
  }

  void setupBoard() override {}

  void resetBoard() override { pulse_ = {0, 0, 0, 0}; }

  RxResult onRpdo(const CanFrame& f) override {
    if (f.id != 0x200u + nodeId()) return RxResult::kUnknown;
    if (f.dlc != 8) return RxResult::kMalformed;
    for (int i = 0; i < 4; ++i) {
      const uint16_t p = get16(f, 2 * i);
      if (p != 0 && (p < 500 || p > 2500)) continue;  // the firmware ignores impossible pulses
      pulse_[i] = p;
      if (p != 0 && !servos_[i].empty()) world().setServoTarget(servos_[i], (p - 1500.0) / 500.0 * M_PI / 2.0);
    }
    return RxResult::kOk;
  }

  bool onRtr(uint32_t cob, CanFrame& out) override {
    if (cob == 0x180u + nodeId()) {
      out = CanFrame::make(cob, {0, 0, 0, 0, 0, 0, 0, 0});
      for (int i = 0; i < 4; ++i) {
        adc_[i] = adc(i);
        put16(out, 2 * i, adc_[i]);
      }
      return true;
    }
    if (cob == 0x280u + nodeId()) {
      out = CanFrame::make(cob, {0, 0});
      put16(out, 0, switchBits());
      return true;
    }
    return false;
  }

  void tick(double) override {}

  void truth(CanFirmware& m) override {
    m.names = {"pulse0", "pulse1", "pulse2", "pulse3", "adc0", "adc1", "adc2", "adc3", "switches"};
    m.values = {double(pulse_[0]), double(pulse_[1]), double(pulse_[2]), double(pulse_[3]), double(adc_[0]),
                double(adc_[1]), double(adc_[2]), double(adc_[3]), double(switchBits())};
  }

 private:
  // GP2D12 output voltage for a distance [m] (typical curve of the datasheet).
  static double gp2d12Volts(double d) {
    static const double kD[] = {0.10, 0.15, 0.20, 0.25, 0.30, 0.40, 0.50, 0.60, 0.70, 0.80};
    static const double kV[] = {2.40, 1.65, 1.30, 1.08, 0.92, 0.73, 0.60, 0.51, 0.45, 0.40};
    if (!std::isfinite(d) || d > 1.0) return 0.30;
    if (d > 0.80) return 0.40 - (d - 0.80) * 0.5;
    if (d < 0.10) return std::max(0.0, 2.40 + (0.10 - d) * 4.0);  // the near zone: ambiguous, high
    for (int i = 0; i < 9; ++i)
      if (d <= kD[i + 1]) return kV[i] + (kV[i + 1] - kV[i]) * (d - kD[i]) / (kD[i + 1] - kD[i]);
    return 0.40;
  }
  uint16_t adc(int i) {
    if (rangers_[i].empty()) return 0;
    const double v = gp2d12Volts(world().measureRange(rangers_[i]));
    const long raw = std::lround(v / 5.0 * 1023.0) + noise_(rng_);
    return static_cast<uint16_t>(std::max(0L, std::min(1023L, raw)));
  }
  uint16_t switchBits() {
    uint16_t b = 0;
    for (std::size_t i = 0; i < switches_.size(); ++i)
      if (!switches_[i].empty() && world().switchClosed(switches_[i])) b |= static_cast<uint16_t>(1u << i);
    return b;
  }

  std::vector<std::string> servos_, rangers_, switches_;
  std::array<uint16_t, 4> pulse_{0, 0, 0, 0}, adc_{0, 0, 0, 0};
  std::mt19937 rng_{7};
  std::uniform_int_distribution<int> noise_{-1, 1};
};

ROBOT_SIM_REGISTER_FIRMWARE("ServoBoard", CanServoBoardFirmware);

}  // namespace robot_sim
