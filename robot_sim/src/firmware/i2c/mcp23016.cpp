// Emulator of the MCP23016 I/O expander (datasheet register map; pairs toggle: after
// GP0 comes GP1, after GP1 comes GP0 again).
//
// Parameters: robot_sim/PARAMETERS.md (MCP23016); with a world a closed switch pulls its pin to
// ground (reads 0); without one, ~input_levels is followed live.
// Truth (tests only): /sim/<name>/outputs (std_msgs/UInt16: OLAT on output pins, 20 Hz).
// Faults: "board_silent", "board_reset" (registers back to power-on: IODIR 0xFFFF, rest 0).
#include <std_msgs/UInt16.h>

#include <optional>

#include "register_chip.h"
#include "robot_sim/firmware/firmware_registry.h"
#include "robot_sim/world/world.h"

namespace robot_sim {

class MCP23016Firmware : public RegisterChip {
 public:
  ~MCP23016Firmware() override { stop(); }

  void configure(const robot_core::Params& params) override {
    readBus(params, 0x20, 0x27);
    params.describe("pins", "with a world: the world's switch on each pin, pin i <- pins[i] (\"\" unconnected; at most 16)");
    pins_ = params.optionalStringList("pins");
    if (pins_.size() > 16) params.check("pins", "at most 16 pins");
    params.describe("input_levels", "without a world: the 16 pin levels, bit i pin i (followed live: rosparam set; "
                                    "0xFFFF every pin pulled up)");
    input_levels_ = params.optionalInt("input_levels", 0xFFFF);
    params.requireInRange("input_levels", input_levels_, 0, 0xFFFF);
  }

  void start(FirmwareContext& ctx) override {
    world_ = ctx.world;
    pnh_ = ctx.pnh;
    powerOn();
    truth_pub_ = ctx.nh.advertise<std_msgs::UInt16>("/sim/" + ctx.name + "/outputs", 10, true);
    truth_timer_ = ctx.nh.createWallTimer(ros::WallDuration(0.05), [this](const ros::WallTimerEvent&) {
      std_msgs::UInt16 m;
      std::lock_guard<std::mutex> lk(mutex_);
      m.data = olat_ & static_cast<uint16_t>(~iodir_);
      truth_pub_.publish(m);
    });
    attachBus(ctx);
  }

  void stop() override {
    detachBus();
    truth_timer_.stop();
  }

  bool resettable() const override { return true; }
  void resetToPowerOn() override {
    std::lock_guard<std::mutex> lk(mutex_);
    powerOn();
  }

 protected:
  uint8_t readRegister(uint8_t reg, bool /*first*/) override {
    std::lock_guard<std::mutex> lk(mutex_);
    const int port = reg & 1;
    auto byte = [port](uint16_t v) { return static_cast<uint8_t>(port ? v >> 8 : v & 0xFF); };
    switch (reg & 0xFE) {
      case 0x00: {
        const uint16_t in = static_cast<uint16_t>((pinLevels() ^ ipol_) & iodir_);
        return byte(static_cast<uint16_t>(in | (olat_ & ~iodir_)));
      }
      case 0x02: return byte(olat_);
      case 0x04: return byte(ipol_);
      case 0x06: return byte(iodir_);
      case 0x08: return byte(intcap_);
      case 0x0A: return byte(iocon_);
      default: return 0;
    }
  }

  void writeRegister(uint8_t reg, uint8_t value) override {
    std::lock_guard<std::mutex> lk(mutex_);
    auto set = [&](uint16_t& v) {
      v = (reg & 1) ? static_cast<uint16_t>((v & 0x00FF) | (value << 8)) : static_cast<uint16_t>((v & 0xFF00) | value);
    };
    switch (reg & 0xFE) {
      case 0x00: case 0x02: set(olat_); break;  // writing GP writes the latch
      case 0x04: set(ipol_); break;
      case 0x06: set(iodir_); break;
      case 0x0A: set(iocon_); break;
      default: break;
    }
  }

  uint8_t nextPointer(uint8_t reg) override { return static_cast<uint8_t>(reg ^ 1); }

 private:
  void powerOn() {
    olat_ = ipol_ = intcap_ = iocon_ = 0;
    iodir_ = 0xFFFF;
  }

  uint16_t pinLevels() {
    if (!world_) {
      int levels = input_levels_;
      pnh_->getParamCached("input_levels", levels);
      return static_cast<uint16_t>(levels);
    }
    uint16_t v = 0xFFFF;
    for (std::size_t i = 0; i < pins_.size(); ++i)
      if (!pins_[i].empty() && world_->switchClosed(pins_[i])) v &= static_cast<uint16_t>(~(1u << i));
    return v;
  }

  World* world_ = nullptr;
  std::optional<ros::NodeHandle> pnh_;  // set by start(): configure() alone needs no ros::init
  int input_levels_ = 0xFFFF;
  std::vector<std::string> pins_;
  std::mutex mutex_;
  uint16_t olat_ = 0, ipol_ = 0, iodir_ = 0xFFFF, intcap_ = 0, iocon_ = 0;
  ros::Publisher truth_pub_;
  ros::WallTimer truth_timer_;
};

ROBOT_SIM_REGISTER_FIRMWARE("MCP23016", MCP23016Firmware);

}  // namespace robot_sim
