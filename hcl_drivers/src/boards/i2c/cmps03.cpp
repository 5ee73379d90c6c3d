// CMPS03: magnetic compass on I2C (cmps03_registers.h).
//
// Parameters: only rate/loop and the I2C ones (boards/i2c_device.h, read and described in
// I2cConfig::read(); the table: hcl_drivers/PARAMETERS.md, make docs). ~address is 0x60, the
// CMPS03's only address: a parameter so a bus scan result can be used.
// Topics: ~bearing (hcl_drivers/Bearing, latched: 0..359.9 degrees clockwise from north),
//         ~state (hcl_drivers/CMPS03State, latched).
// Each service() reads 0x00..0x03 (revision, byte bearing, word bearing) in one combined
// transaction; a word beyond 3599 or disagreeing with the byte bearing is counted and dropped.
#include <hcl_drivers/Bearing.h>
#include <hcl_drivers/CMPS03State.h>

#include <mutex>

#include <robot_core/priority_inheritance_mutex.h>

#include "hcl_drivers/board_nodelet.h"
#include "hcl_drivers/boards/cmps03_registers.h"
#include "hcl_drivers/boards/i2c_device.h"

namespace hcl_drivers {

class CMPS03 : public Board {
 public:
  void configure(const robot_core::Params& p) override { i2c_ = I2cConfig::read(p, 0x08, 0x77); }

  void init(BoardContext& ctx) override {
    dev_ = openI2cDevice(i2c_);
    bearing_pub_ = ctx.pnh.advertise<Bearing>("bearing", 1, true);
    state_pub_ = ctx.pnh.advertise<CMPS03State>("state", 1, true);
  }

  void check(BoardContext& /*ctx*/, CheckReport& report) override {
    I2cDevice dev;
    std::vector<uint8_t> raw;
    if (!checkI2cIdentity(i2c_, cmps03::kRegRevision, cmps03::kBlockSize, dev, raw, report)) return;
    const auto r = cmps03::decodeBlock(raw);
    if (r)
      report.ok("identity", "CMPS03 revision and a bearing",
                "revision " + std::to_string(r->revision) + ", bearing " + std::to_string(r->degrees()).substr(0, 5) + " deg");
    else
      report.fail("identity", "CMPS03 revision and a bearing", "bytes that are no CMPS03 bearing",
                  "another chip answers at this address: check the address jumpers / the config's address");
  }

  bool service() override {
    auto addr_lock = dev_.bus->lockAddress(dev_.address);
    std::string err;
    std::vector<uint8_t> raw;
    if (dev_.bus->readRegisters(dev_.address, cmps03::kRegRevision, cmps03::kBlockSize, raw, err) !=
        transport::I2cStatus::kOk) {
      fail(err);
      return false;
    }
    const auto r = cmps03::decodeBlock(raw);
    if (!r) {
      std::lock_guard lk(mutex_);
      ++garbled_;
      fail("garbled bearing (word > 3599 or byte/word disagree)");
      return false;
    }
    const ros::Time now = ros::Time::now();
    Bearing::Ptr b(new Bearing);
    b->header.stamp = now;
    b->degrees = r->degrees();
    bearing_pub_.publish(b);
    CMPS03State::Ptr s(new CMPS03State);
    s->header.stamp = now;
    s->address = dev_.address;
    s->revision = r->revision;
    s->bearing_byte = r->bearing_byte;
    s->bearing_word = r->bearing_word;
    state_pub_.publish(s);
    return true;
  }

  void halt() override {}  // a sensor: nothing to make safe

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    diagnoseI2c(dev_, stat);
    std::lock_guard lk(mutex_);
    stat.add("garbled reads", garbled_);
  }

 private:
  I2cConfig i2c_;  // the I2C parameters configure() read
  I2cDevice dev_;
  ros::Publisher bearing_pub_, state_pub_;
  robot_core::PriorityInheritanceMutex mutex_;
  unsigned long garbled_ = 0;
};

}  // namespace hcl_drivers

HCL_EXPORT_BOARD(CMPS03, "CMPS03 I2C magnetic compass (bearing 0..359.9 degrees).")
