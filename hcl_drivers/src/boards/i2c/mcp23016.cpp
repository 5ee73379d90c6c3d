// MCP23016: 16-bit I/O expander (mcp23016_registers.h). On Logion: buttons in, LEDs out.
//
// Parameters (besides rate/loop and the I2C ones in boards/i2c_device.h): read and described in
// configure() (the table: hcl_drivers/PARAMETERS.md, make docs).
// Topics: ~inputs (hcl_drivers/DigitalInputs, latched: bits = GP & IODIR),
//         ~outputs (std_msgs/UInt16 in: OLAT bits; only pins configured as outputs drive),
//         ~state (hcl_drivers/MCP23016State, latched).
// Each service() writes OLAT, then reads GP and IODIR in one combined transaction; IODIR
// back at its power-on value (0xFFFF while we configured outputs) means the chip reset,
// and it is configured again.
#include <hcl_drivers/DigitalInputs.h>
#include <hcl_drivers/MCP23016State.h>
#include <std_msgs/UInt16.h>

#include <mutex>

#include <robot_core/priority_inheritance_mutex.h>

#include "hcl_drivers/board_nodelet.h"
#include "hcl_drivers/boards/i2c_device.h"
#include "hcl_drivers/boards/mcp23016_registers.h"

namespace hcl_drivers {

using robot_core::ParameterError;

class MCP23016 : public Board {
 public:
  void configure(const robot_core::Params& p) override {
    i2c_ = I2cConfig::read(p, mcp23016::kAddressMin, mcp23016::kAddressMax);
    p.describe("direction", "IODIR, 16 bits, 1 = input");
    const int dir = p.optionalInt("direction", 0xFFFF);
    p.requireInRange("direction", dir, 0, 0xFFFF);
    p.describe("input_polarity", "IPOL, 16 bits, 1 = invert that input (buttons to ground read 1 when pressed)");
    const int pol = p.optionalInt("input_polarity", 0);
    p.requireInRange("input_polarity", pol, 0, 0xFFFF);
    p.describe("outputs_initial", "OLAT, 16 bits, written at start and after halt (on Logion: the LEDs)");
    const int out = p.optionalInt("outputs_initial", 0);
    p.requireInRange("outputs_initial", out, 0, 0xFFFF);
    direction_ = static_cast<uint16_t>(dir);
    polarity_ = static_cast<uint16_t>(pol);
    initial_ = olat_ = static_cast<uint16_t>(out);
    p.describe("input_names", "names of the input bits 0.. (at most 16), copied into DigitalInputs.names");
    names_ = p.optionalStringList("input_names");  // "must be a list of strings" otherwise
    if (names_.size() > 16)
      throw ParameterError("parameter " + p.qualified("input_names") + ": at most 16 names (one per pin)");
  }

  void init(BoardContext& ctx) override {
    dev_ = openI2cDevice(i2c_);
    inputs_pub_ = ctx.pnh.advertise<DigitalInputs>("inputs", 1, true);
    state_pub_ = ctx.pnh.advertise<MCP23016State>("state", 1, true);
    outputs_sub_ = subscribeCommand<std_msgs::UInt16>(ctx, "outputs", [this](const std_msgs::UInt16::ConstPtr& m) { onOutputs(m); });
  }

  // Identity by read-back: the configured input polarity (IPOL, harmless: the driver writes
  // the same at start) must read back as written.
  void check(BoardContext& /*ctx*/, CheckReport& report) override {
    I2cDevice dev;
    std::vector<uint8_t> raw;
    if (!checkI2cIdentity(i2c_, mcp23016::kRegIpol0, 2, dev, raw, report)) return;
    const int polarity = polarity_;
    std::string err;
    std::vector<uint8_t> back;
    char expected[32], found[48];
    std::snprintf(expected, sizeof expected, "IPOL 0x%04x read back", polarity & 0xFFFF);
    if (dev.bus->writeRegisters(dev.address, mcp23016::kRegIpol0, mcp23016::encodePair(static_cast<uint16_t>(polarity)), err) !=
            transport::I2cStatus::kOk ||
        dev.bus->readRegisters(dev.address, mcp23016::kRegIpol0, 2, back, err) != transport::I2cStatus::kOk) {
      report.fail("identity", expected, "write/read failed: " + err, "check the wiring (SDA/SCL, pull-ups)");
      return;
    }
    const uint16_t read = mcp23016::decodePair(back);
    std::snprintf(found, sizeof found, "0x%04x", read);
    if (read == (polarity & 0xFFFF))
      report.ok("identity", expected, found);
    else
      report.fail("identity", expected, found, "another chip answers at this address: check its A0..A2 pins and the config");
  }

  bool service() override {
    auto addr_lock = dev_.bus->lockAddress(dev_.address);
    std::string err;
    using transport::I2cStatus;
    if (!configured_) {
      if (dev_.bus->writeRegisters(dev_.address, mcp23016::kRegOlat0, mcp23016::encodePair(olat()), err) != I2cStatus::kOk ||
          dev_.bus->writeRegisters(dev_.address, mcp23016::kRegIpol0, mcp23016::encodePair(polarity_), err) !=
              I2cStatus::kOk ||
          dev_.bus->writeRegisters(dev_.address, mcp23016::kRegIodir0, mcp23016::encodePair(direction_), err) !=
              I2cStatus::kOk) {
        fail(err);
        return false;
      }
      configured_ = true;
    }
    const uint16_t olat_now = olat();
    if (dev_.bus->writeRegisters(dev_.address, mcp23016::kRegOlat0, mcp23016::encodePair(olat_now), err) != I2cStatus::kOk) {
      fail(err);
      return false;
    }
    std::vector<transport::I2cMessage> msgs(4);
    for (auto& m : msgs) m.address = dev_.address;
    msgs[0].data = {mcp23016::kRegGp0};
    msgs[1].read = true;
    msgs[1].data.assign(2, 0);
    msgs[2].data = {mcp23016::kRegIodir0};
    msgs[3].read = true;
    msgs[3].data.assign(2, 0);
    if (dev_.bus->transfer(msgs, err) != I2cStatus::kOk) {
      fail(err);
      return false;
    }
    const uint16_t gp = mcp23016::decodePair(msgs[1].data);
    const uint16_t iodir = mcp23016::decodePair(msgs[3].data);
    if (iodir != direction_) {
      std::lock_guard lk(mutex_);
      configured_ = false;
      if (iodir == mcp23016::kIodirPowerOn) {
        ++resets_;
        ROS_WARN("MCP23016 0x%02x reset (IODIR at power-on value): reconfiguring", dev_.address);
      } else {
        ++mismatches_;
      }
      fail("IODIR reads 0x" + hex(iodir) + ", configured 0x" + hex(direction_) + ": reconfiguring");
      return false;
    }
    publish(gp, iodir, olat_now);
    return true;
  }

  void halt() override {
    // LEDs are harmless but a halted board should look halted: back to the initial outputs.
    {
      std::lock_guard lk(mutex_);
      olat_ = initial_;
    }
    if (!dev_.bus) return;
    auto addr_lock = dev_.bus->lockAddress(dev_.address);
    std::string err;
    dev_.bus->writeRegisters(dev_.address, mcp23016::kRegOlat0, mcp23016::encodePair(initial_), err);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    diagnoseI2c(dev_, stat);
    std::lock_guard lk(mutex_);
    stat.add("board resets seen", resets_);
    stat.add("IODIR mismatches", mismatches_);
    stat.addf("outputs", "0x%04x", olat_);
  }

 private:
  static std::string hex(uint16_t v) {
    char b[8];
    std::snprintf(b, sizeof(b), "%04x", v);
    return b;
  }

  void onOutputs(const std_msgs::UInt16::ConstPtr& msg) {
    std::lock_guard lk(mutex_);
    olat_ = msg->data;
  }

  uint16_t olat() {
    std::lock_guard lk(mutex_);
    return olat_;
  }

  void publish(uint16_t gp, uint16_t iodir, uint16_t olat) {
    const ros::Time now = ros::Time::now();
    DigitalInputs::Ptr in(new DigitalInputs);
    in->header.stamp = now;
    in->bits = mcp23016::inputBits(gp, iodir);
    in->names = names_;
    inputs_pub_.publish(in);
    MCP23016State::Ptr s(new MCP23016State);
    s->header.stamp = now;
    s->address = dev_.address;
    s->gp = gp;
    s->iodir = iodir;
    s->olat = olat;
    {
      std::lock_guard lk(mutex_);
      s->board_resets = resets_;
    }
    state_pub_.publish(s);
  }

  I2cConfig i2c_;  // the I2C parameters configure() read
  I2cDevice dev_;
  uint16_t direction_ = 0xFFFF, polarity_ = 0, initial_ = 0;
  std::vector<std::string> names_;
  bool configured_ = false;
  ros::Publisher inputs_pub_, state_pub_;
  ros::Subscriber outputs_sub_;

  robot_core::PriorityInheritanceMutex mutex_;
  uint16_t olat_ = 0;
  uint32_t resets_ = 0;
  unsigned long mismatches_ = 0;
};

}  // namespace hcl_drivers

HCL_EXPORT_BOARD(MCP23016, "MCP23016 I2C 16-bit I/O expander: buttons in, LEDs out.")
