// Emulator of the SRF02 ultrasonic ranger, I2C mode (datasheet register map). A ranging
// command (0x50 inches, 0x51 cm, 0x52 us) measures once and keeps the chip busy for 65 ms:
// meanwhile it does not drive SDA, so every byte read is 0xFF.
//
// Parameters: robot_sim/PARAMETERS.md (SRF02); without a world, ~range is followed live.
// Truth (tests only): /sim/<name>/range (std_msgs/Float64, the distance of the last ranging [m]).
// Faults: "board_silent".
#include <std_msgs/Float64.h>

#include <cmath>
#include <optional>

#include "register_chip.h"
#include "robot_sim/firmware/firmware_registry.h"
#include "robot_sim/world/world.h"

namespace robot_sim {

class SRF02Firmware : public RegisterChip {
 public:
  ~SRF02Firmware() override { stop(); }

  void configure(const robot_core::Params& params) override {
    readBus(params, 0x70, 0x7F);
    params.describe("ranger", "with a world: the world's ranger it measures with");
    ranger_ = params.optionalString("ranger", "");
    params.describe("range", "[m] without a world: the distance it measures (followed live: rosparam set)");
    range_ = params.optionalDouble("range", 1.0);
    params.describe("conversion_time", "[s] how long a ranging keeps the chip busy (every byte read 0xFF meanwhile)");
    conversion_ = params.optionalDouble("conversion_time", 0.065);
    params.requirePositive("conversion_time", conversion_);
  }

  void start(FirmwareContext& ctx) override {
    world_ = ctx.world;
    pnh_ = ctx.pnh;
    if (world_ && (ranger_.empty() || !world_->has("ranger", ranger_)))
      throw std::runtime_error("parameter " + ctx.params.qualified("ranger") + " = '" + ranger_ + "': no such ranger in the world");
    truth_pub_ = ctx.nh.advertise<std_msgs::Float64>("/sim/" + ctx.name + "/range", 10, true);
    attachBus(ctx);
  }

  void stop() override { detachBus(); }

 protected:
  uint8_t readRegister(uint8_t reg, bool /*first*/) override {
    if (ros::Time::now() < busy_until_) return 0xFF;  // converting: SDA floats high
    switch (reg) {
      case 0x00: return 0x06;  // software revision
      case 0x01: return 0x80;
      case 0x02: return static_cast<uint8_t>(result_ >> 8);
      case 0x03: return static_cast<uint8_t>(result_ & 0xFF);
      case 0x04: return 0x00;
      case 0x05: return 0x10;  // autotune minimum: 16 cm
      default: return 0x00;
    }
  }

  void writeRegister(uint8_t reg, uint8_t value) override {
    if (reg != 0x00 || value < 0x50 || value > 0x52) return;
    double m = range_;
    if (world_)
      m = world_->measureRange(ranger_);
    else
      pnh_->getParamCached("range", m);
    std_msgs::Float64 t;
    t.data = m;
    truth_pub_.publish(t);
    // No echo within 6 m reads 0, as the real part does.
    if (!std::isfinite(m) || m > 6.0 || m < 0.0) {
      result_ = 0;
    } else {
      const double cm = std::max(16.0, m * 100.0);  // the SRF02 cannot see closer than ~16 cm
      result_ = static_cast<uint16_t>(std::lround(value == 0x50 ? cm / 2.54 : value == 0x52 ? cm * 58.0 : cm));
    }
    busy_until_ = ros::Time::now() + ros::Duration(conversion_);
  }

 private:
  World* world_ = nullptr;
  std::optional<ros::NodeHandle> pnh_;  // set by start(): configure() alone needs no ros::init
  double range_ = 1.0;
  std::string ranger_;
  double conversion_ = 0.065;
  uint16_t result_ = 0;
  ros::Time busy_until_;
  ros::Publisher truth_pub_;
};

ROBOT_SIM_REGISTER_FIRMWARE("SRF02", SRF02Firmware);

}  // namespace robot_sim
