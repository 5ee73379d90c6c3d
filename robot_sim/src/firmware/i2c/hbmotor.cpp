// Emulator of Logion's HBmotor board (register map: hcl_drivers/boards/hbmotor_registers.h,
// reimplemented here from that text). One H-bridge and one 32-bit encoder counter.
//
// Parameters: robot_sim/PARAMETERS.md (HBMotor).
// Truth (tests only): /sim/<name>/duty (std_msgs/Int32, the duty the H-bridge applies, 50 Hz).
// Faults: "board_silent" (NACKs), "board_reset" (power-on state: flag set, watchdog off,
// counter 0, motor off).
#include <std_msgs/Int32.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

#include "register_chip.h"
#include "robot_sim/firmware/firmware_registry.h"
#include "robot_sim/world/world.h"
#include <robot_core/realtime.h>

namespace robot_sim {

class HBMotorFirmware : public RegisterChip {
 public:
  ~HBMotorFirmware() override { stop(); }

  void configure(const robot_core::Params& params) override {
    readBus(params, 0x08, 0x77);
    params.describe("motor", "with a world: the world's motor the H-bridge drives");
    motor_ = params.optionalString("motor", "");
    params.describe("encoder", "with a world: the world's encoder it counts (default: the motor's; \"\" none)");
    encoder_ = params.optionalString("encoder", motor_);
    params.describe("ticks_per_second", "without a world: encoder counts per second at full command");
    ticks_per_second_ = params.optionalDouble("ticks_per_second", 2000.0);
    params.requirePositive("ticks_per_second", ticks_per_second_);
  }

  void start(FirmwareContext& ctx) override {
    world_ = ctx.world;
    if (world_ && (motor_.empty() || !world_->has("motor", motor_)))
      throw std::runtime_error("parameter " + ctx.params.qualified("motor") + " = '" + motor_ + "': no such motor in the world");
    if (world_ && !encoder_.empty() && !world_->has("encoder", encoder_))
      throw std::runtime_error("parameter " + ctx.params.qualified("encoder") + " = '" + encoder_ + "': no such encoder in the world");
    powerOn();
    truth_pub_ = ctx.nh.advertise<std_msgs::Int32>("/sim/" + ctx.name + "/duty", 10);
    attachBus(ctx);
    running_ = true;
    thread_ = std::thread([this] { run(); });
  }

  void stop() override {
    detachBus();
    running_ = false;
    if (thread_.joinable()) thread_.join();
    if (world_ && !motor_.empty()) world_->setMotorCommand(motor_, 0.0);
  }

  bool resettable() const override { return true; }
  void resetToPowerOn() override {
    std::lock_guard<std::mutex> lk(mutex_);
    powerOn();
  }

 protected:
  uint8_t readRegister(uint8_t reg, bool /*first*/) override {
    std::lock_guard<std::mutex> lk(mutex_);
    if (reg == 0x04) latched_ = encoderNow();  // latched when 0x04 is addressed
    switch (reg) {
      case 0x00: return 0x12;
      case 0x01: return status_ | (duty_ != 0 ? 0x01 : 0x00);
      case 0x02: return static_cast<uint8_t>(duty_);
      case 0x03: return 0;
      case 0x04: case 0x05: case 0x06: case 0x07: return static_cast<uint8_t>(latched_ >> (8 * (reg - 0x04)));
      case 0x08: return watchdog_;
      default: return 0xFF;
    }
  }

  void writeRegister(uint8_t reg, uint8_t value) override {
    std::lock_guard<std::mutex> lk(mutex_);
    switch (reg) {
      case 0x02: {
        int8_t d = static_cast<int8_t>(value);
        if (d == -128) d = -127;
        setDuty(d);
        last_command_ = firmwareNow();
        status_ &= ~0x04;
        break;
      }
      case 0x03:
        if (value & 0x01) status_ &= ~0x80;
        if (value & 0x02) offset_ = rawTicks();
        break;
      case 0x08: watchdog_ = value; break;
      default: break;  // read-only or unused: ignored like the AVR does
    }
  }

 private:
  void powerOn() {
    status_ = 0x80;
    watchdog_ = 0;
    setDuty(0);
    offset_ = rawTicks();
  }

  void setDuty(int8_t d) {
    duty_ = d;
    if (world_) world_->setMotorCommand(motor_, d / 127.0);
  }

  // ~encoder "" with a world: no encoder connected, the counter stays 0.
  int64_t rawTicks() const {
    if (world_) return encoder_.empty() ? 0 : world_->encoderTicks(encoder_);
    return static_cast<int64_t>(std::floor(model_ticks_));
  }
  uint32_t encoderNow() const { return static_cast<uint32_t>(rawTicks() - offset_); }

  // The firmware's main loop: watchdog, and the world-less motor model.
  void run() {
    robot_core::enterRealtime("an I2C board emulator");
    double last = firmwareNow();  // the board's clock: simulated time in a simulation
    int n = 0;
    while (running_) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      const double now = firmwareNow();
      std_msgs::Int32 truth;
      {
        std::lock_guard<std::mutex> lk(mutex_);
        const double dt = std::max(0.0, now - last);
        if (!world_) model_ticks_ += duty_ / 127.0 * ticks_per_second_ * dt;
        if (watchdog_ != 0 && duty_ != 0 && now - last_command_ > 0.01 * watchdog_) {
          setDuty(0);
          status_ |= 0x04;
        }
        truth.data = duty_;
      }
      last = now;
      if (++n % 4 == 0) truth_pub_.publish(truth);
    }
  }

  World* world_ = nullptr;
  std::string motor_, encoder_;
  double ticks_per_second_ = 2000.0;
  std::mutex mutex_;
  uint8_t status_ = 0x80, watchdog_ = 0;
  int8_t duty_ = 0;
  int64_t offset_ = 0;
  double model_ticks_ = 0.0;
  uint32_t latched_ = 0;
  double last_command_ = 0.0;  // on the board's clock
  std::atomic<bool> running_{false};
  std::thread thread_;
  ros::Publisher truth_pub_;
};

ROBOT_SIM_REGISTER_FIRMWARE("HBMotor", HBMotorFirmware);

}  // namespace robot_sim
