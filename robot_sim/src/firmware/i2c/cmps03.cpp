// Emulator of the CMPS03 compass, I2C mode (datasheet register map). The bearing is
// sampled when a read addresses register 0x00 or 0x01, so one block read is consistent.
//
// Parameters: robot_sim/PARAMETERS.md (CMPS03); without a world, ~bearing is followed live.
// Truth (tests only): /sim/<name>/bearing (std_msgs/Float64, the bearing last sampled [deg]).
// Faults: "board_silent".
#include <std_msgs/Float64.h>

#include <cmath>
#include <optional>

#include "register_chip.h"
#include "robot_sim/firmware/firmware_registry.h"
#include "robot_sim/world/world.h"

namespace robot_sim {

class CMPS03Firmware : public RegisterChip {
 public:
  ~CMPS03Firmware() override { stop(); }

  void configure(const robot_core::Params& params) override {
    readBus(params, 0x08, 0x77);
    params.describe("bearing", "[deg] without a world: the bearing it reports (followed live: rosparam set)");
    bearing_ = params.optionalDouble("bearing", 0.0);
  }

  void start(FirmwareContext& ctx) override {
    world_ = ctx.world;
    pnh_ = ctx.pnh;
    truth_pub_ = ctx.nh.advertise<std_msgs::Float64>("/sim/" + ctx.name + "/bearing", 10, true);
    attachBus(ctx);
  }

  void stop() override { detachBus(); }

 protected:
  uint8_t readRegister(uint8_t reg, bool first) override {
    if (first && reg <= 0x01) sample();
    switch (reg) {
      case 0x00: return 0x0E;
      case 0x01: return static_cast<uint8_t>(std::lround(word_ * 256.0 / 3600.0) & 0xFF);
      case 0x02: return static_cast<uint8_t>(word_ >> 8);
      case 0x03: return static_cast<uint8_t>(word_ & 0xFF);
      default: return 0x00;
    }
  }
  void writeRegister(uint8_t, uint8_t) override {}  // calibration commands: accepted, no effect

 private:
  void sample() {
    double deg = bearing_;
    if (world_)
      deg = world_->measureCompassDeg();
    else
      pnh_->getParamCached("bearing", deg);
    deg = std::fmod(deg, 360.0);
    if (deg < 0.0) deg += 360.0;
    word_ = static_cast<uint16_t>(std::lround(deg * 10.0) % 3600);
    std_msgs::Float64 t;
    t.data = word_ / 10.0;
    truth_pub_.publish(t);
  }

  World* world_ = nullptr;
  std::optional<ros::NodeHandle> pnh_;  // set by start(): configure() alone needs no ros::init
  double bearing_ = 0.0;
  uint16_t word_ = 0;
  ros::Publisher truth_pub_;
};

ROBOT_SIM_REGISTER_FIRMWARE("CMPS03", CMPS03Firmware);

}  // namespace robot_sim
