// Emulator of the CAN human interface board firmware (2x16 character LCD, 4x4 keypad):
//   RPDO1 0x200+n [line u8, column u8, 1..6 characters]   TPDO1 0x180+n [keys u16, last key u8, presses u8]
// Keys are world switches (default names hmi_key_0 .. hmi_key_15; /sim/set_switch presses them);
// the LCD content is the truth's `text` ("line0\nline1").
// Parameters: robot_sim/PARAMETERS.md (HmiBoard).
#include "canopen_firmware.h"
#include "robot_sim/firmware/firmware_registry.h"

namespace robot_sim {

class CanHmiBoardFirmware : public CanopenFirmware {
 protected:
  void readBoardParams(const robot_core::Params& params) override {
    params.describe("keys", "the world's switches of the 16 keys in key order (default hmi_key_0 .. hmi_key_15)");
    keys_ = params.optionalStringList("keys");
    if (keys_.size() > 16) params.check("keys", "at most 16 names");
    if (!params.has("keys"))
      for (int i = 0; i < 16; ++i) keys_.push_back("hmi_key_" + std::to_string(i));
    keys_.resize(16);
  }

  void setupBoard() override {}

  void resetBoard() override {
    lcd_[0].assign(16, ' ');
    lcd_[1].assign(16, ' ');
    held_ = 0;
    last_key_ = 255;
    presses_ = 0;
  }

  RxResult onRpdo(const CanFrame& f) override {
    if (f.id != 0x200u + nodeId()) return RxResult::kUnknown;
    if (f.dlc < 3 || f.data[0] > 1 || f.data[1] > 15) return RxResult::kMalformed;
    for (int i = 2; i < f.dlc; ++i) {
      const int col = f.data[1] + i - 2;
      if (col < 16) lcd_[f.data[0]][col] = static_cast<char>(f.data[i]);
    }
    return RxResult::kOk;
  }

  bool onRtr(uint32_t cob, CanFrame& out) override {
    if (cob != 0x180u + nodeId()) return false;
    scan();
    out = CanFrame::make(cob, {0, 0, last_key_, presses_});
    put16(out, 0, held_);
    return true;
  }

  void tick(double) override { scan(); }

  void truth(CanFirmware& m) override {
    m.names = {"keys", "last_key", "presses"};
    m.values = {double(held_), double(last_key_), double(presses_)};
    m.text = lcd_[0] + "\n" + lcd_[1];
  }

 private:
  void scan() {
    uint16_t now_held = 0;
    for (int i = 0; i < 16; ++i)
      if (!keys_[i].empty() && world().switchClosed(keys_[i])) now_held |= static_cast<uint16_t>(1u << i);
    const uint16_t pressed = now_held & ~held_;
    for (int i = 0; i < 16; ++i)
      if (pressed & (1u << i)) {
        last_key_ = static_cast<uint8_t>(i);
        ++presses_;
      }
    held_ = now_held;
  }

  std::vector<std::string> keys_;
  std::string lcd_[2];
  uint16_t held_ = 0;
  uint8_t last_key_ = 255, presses_ = 0;
};

ROBOT_SIM_REGISTER_FIRMWARE("HmiBoard", CanHmiBoardFirmware);

}  // namespace robot_sim
