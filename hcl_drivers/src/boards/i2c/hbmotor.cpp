// HBmotor: Logion's I2C H-bridge board, one motor and its encoder (hbmotor_registers.h).
//
// Parameters (besides rate/loop and the I2C ones in boards/i2c_device.h): read and described in
// configure() (the table: hcl_drivers/PARAMETERS.md, make docs).
// Topics: ~motor/<motor>/command (hcl_drivers/MotorCommand in, value = PWM duty -127..127),
//         ~encoder/<encoder> (hcl_drivers/EncoderCounter, latched, bits = 32),
//         ~state (hcl_drivers/HBMotorState, latched).
// Every service() writes COMMAND (feeding the firmware watchdog) then reads 0x00..0x08 in
// one combined transaction.
#include <hcl_drivers/EncoderCounter.h>
#include <hcl_drivers/HBMotorState.h>
#include <hcl_drivers/MotorCommand.h>

#include <mutex>

#include <robot_core/priority_inheritance_mutex.h>

#include "hcl_drivers/board_nodelet.h"
#include "hcl_drivers/boards/hbmotor_registers.h"
#include "hcl_drivers/boards/i2c_device.h"

namespace hcl_drivers {

class HBMotor : public Board {
 public:
  void configure(const robot_core::Params& p) override {
    i2c_ = I2cConfig::read(p, 0x08, 0x77);
    p.describe("motor", "motor name: the command topic is ~motor/<motor>/command");
    motor_ = p.optionalString("motor", "motor");
    p.describe("encoder", "encoder name: the counter topic is ~encoder/<encoder>; when absent the motor name");
    encoder_ = p.optionalString("encoder", motor_);
    p.describe("command_timeout", "[s] a MotorCommand older than this is dropped and 0 written");
    command_timeout_ = p.optionalDouble("command_timeout", 0.3);
    p.requirePositive("command_timeout", command_timeout_);
    p.describe("firmware_watchdog", "[s] written to WATCHDOG: the board stops the motor when the driver stops writing; 0 = off");
    const double wd = p.optionalDouble("firmware_watchdog", 0.25);
    p.requireInRange("firmware_watchdog", wd, 0.0, 2.55);
    watchdog_ = hbmotor::encodeWatchdog(wd);
  }

  void init(BoardContext& ctx) override {
    dev_ = openI2cDevice(i2c_);
    state_pub_ = ctx.pnh.advertise<HBMotorState>("state", 1, true);
    encoder_pub_ = ctx.pnh.advertise<EncoderCounter>("encoder/" + encoder_, 1, true);
    command_sub_ = subscribeCommand<MotorCommand>(ctx, "motor/" + motor_ + "/command", [this](const MotorCommand::ConstPtr& m) { onCommand(m); });
  }

  void check(BoardContext& /*ctx*/, CheckReport& report) override {
    I2cDevice dev;
    std::vector<uint8_t> raw;
    if (!checkI2cIdentity(i2c_, hbmotor::kRegVersion, hbmotor::kBlockSize, dev, raw, report)) return;
    const auto b = hbmotor::decodeBlock(raw);
    if (b)
      report.ok("identity", "HBmotor register block",
                "firmware version " + std::to_string(b->version) + ", status bits " + std::to_string(b->status));
    else
      report.fail("identity", "HBmotor register block", "bytes that are no HBmotor's (reserved status bits set)",
                  "another chip answers at this address: check the board's address and the config");
  }

  bool service() override {
    auto addr_lock = dev_.bus->lockAddress(dev_.address);
    std::string err;
    if (!configured_) {
      // Watchdog first, then clear the power-on flag: a reset seen later means the board rebooted.
      if (dev_.bus->writeRegisters(dev_.address, hbmotor::kRegWatchdog, {watchdog_}, err) != transport::I2cStatus::kOk ||
          dev_.bus->writeRegisters(dev_.address, hbmotor::kRegControl, {hbmotor::kControlClearPowerOn}, err) !=
              transport::I2cStatus::kOk) {
        fail(err);
        return false;
      }
      configured_ = true;
    }
    const int8_t duty = static_cast<int8_t>(hbmotor::encodeCommand(commandToApply()));
    if (dev_.bus->writeRegisters(dev_.address, hbmotor::kRegCommand, {static_cast<uint8_t>(duty)}, err) !=
        transport::I2cStatus::kOk) {
      fail(err);
      return false;
    }
    std::vector<uint8_t> raw;
    if (dev_.bus->readRegisters(dev_.address, hbmotor::kRegVersion, hbmotor::kBlockSize, raw, err) !=
        transport::I2cStatus::kOk) {
      fail(err);
      return false;
    }
    const auto block = hbmotor::decodeBlock(raw);
    if (!block) {
      std::lock_guard lk(mutex_);
      ++garbled_;
      fail("garbled register block (reserved status bits set)");
      return false;
    }
    if (block->status & hbmotor::kStatusPowerOn) {
      // The board rebooted: its counter restarted and its watchdog is off. Reconfigure next time.
      std::lock_guard lk(mutex_);
      ++resets_;
      configured_ = false;
      ROS_WARN("HBmotor 0x%02x reset (power-on flag set): reconfiguring", dev_.address);
    }
    publish(*block, duty);
    return true;
  }

  void halt() override {
    {
      std::lock_guard lk(mutex_);
      command_ = 0;
      command_stamp_ = ros::Time();
    }
    if (!dev_.bus) return;
    auto addr_lock = dev_.bus->lockAddress(dev_.address);
    std::string err;
    dev_.bus->writeRegisters(dev_.address, hbmotor::kRegCommand, {0}, err);  // best effort: motor off
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    diagnoseI2c(dev_, stat);
    std::lock_guard lk(mutex_);
    stat.add("garbled reads", garbled_);
    stat.add("board resets seen", resets_);
    stat.add("commands dropped as stale", stale_commands_);
    stat.add("commands for another motor", wrong_name_);
    stat.add("commands clamped", clamped_);
    stat.add("duty commanded", command_);
  }

 private:
  void onCommand(const MotorCommand::ConstPtr& msg) {
    std::lock_guard lk(mutex_);
    if (!msg->name.empty() && msg->name != motor_) {
      ++wrong_name_;
      return;
    }
    if (msg->value > hbmotor::kCommandMax || msg->value < -hbmotor::kCommandMax) ++clamped_;
    command_ = msg->value;
    command_stamp_ = ros::Time::now();
  }

  int32_t commandToApply() {
    std::lock_guard lk(mutex_);
    if (command_stamp_.isZero()) return 0;
    if ((ros::Time::now() - command_stamp_).toSec() > command_timeout_) {
      ++stale_commands_;
      command_stamp_ = ros::Time();
      command_ = 0;
      ROS_WARN("HBmotor 0x%02x: no command for %.2f s, motor stopped", dev_.address, command_timeout_);
      return 0;
    }
    return command_;
  }

  void publish(const hbmotor::Block& b, int8_t requested) {
    const ros::Time now = ros::Time::now();
    uint32_t resets;
    {
      std::lock_guard lk(mutex_);
      resets = resets_;
    }
    EncoderCounter::Ptr e(new EncoderCounter);
    e->header.stamp = now;
    e->name = encoder_;
    e->raw = b.encoder;
    e->bits = 32;
    e->board_resets = resets;
    encoder_pub_.publish(e);
    HBMotorState::Ptr s(new HBMotorState);
    s->header.stamp = now;
    s->address = dev_.address;
    s->firmware_version = b.version;
    s->status = b.status;
    s->command = b.command;
    s->command_requested = requested;
    s->encoder = b.encoder;
    s->watchdog = b.watchdog;
    s->board_resets = resets;
    state_pub_.publish(s);
  }

  I2cConfig i2c_;  // the I2C parameters configure() read
  I2cDevice dev_;
  std::string motor_, encoder_;
  double command_timeout_ = 0.3;
  uint8_t watchdog_ = 25;
  bool configured_ = false;
  ros::Publisher state_pub_, encoder_pub_;
  ros::Subscriber command_sub_;

  robot_core::PriorityInheritanceMutex mutex_;  // command callback vs polling thread vs diagnostics
  int32_t command_ = 0;
  ros::Time command_stamp_;
  unsigned long garbled_ = 0, stale_commands_ = 0, wrong_name_ = 0, clamped_ = 0;
  uint32_t resets_ = 0;
};

}  // namespace hcl_drivers

HCL_EXPORT_BOARD(HBMotor,
                 "Logion HBmotor I2C H-bridge board: one motor command out, one 32-bit encoder counter in.")
