// SRF02: ultrasonic ranger on I2C (srf02_registers.h), one ranger per board.
//
// The ~65 ms conversion is honoured without blocking the loop (other boards on the same
// bus share this thread): service() is two-phase. It starts a ranging (write 0x51 to the
// command register) and returns; a later service() at least ~conversion_time after the
// start reads the result (4 bytes from 0x00; revision 0xFF = still converting, read again
// next time) and starts the next ranging. So ranges arrive at min(rate, 1/conversion_time).
//
// Parameters (besides rate/loop and the I2C ones in boards/i2c_device.h): read and described in
// configure() (the table: hcl_drivers/PARAMETERS.md, make docs).
// Topics: ~range (sensor_msgs/Range, latched: metres; +inf when the SRF02 reports no echo;
//         stamped at the ranging command, when the ping went out: the echo describes the world
//         then, not when it is read a period later. Stamped at the read, a turning robot's sonars
//         are placed a period's turn off, and the driver takes border echoes for the opponent),
//         ~state (hcl_drivers/SRF02State, latched).
#include <hcl_drivers/SRF02State.h>
#include <sensor_msgs/Range.h>

#include <limits>
#include <mutex>

#include <robot_core/priority_inheritance_mutex.h>

#include "hcl_drivers/board_nodelet.h"
#include "hcl_drivers/boards/i2c_device.h"
#include "hcl_drivers/boards/srf02_registers.h"

namespace hcl_drivers {

class SRF02 : public Board {
 public:
  void configure(const robot_core::Params& p) override {
    i2c_ = I2cConfig::read(p, srf02::kAddressMin, srf02::kAddressMax);
    const std::string base = p.ns().substr(p.ns().rfind('/') + 1);
    p.describe("frame_id", "frame of the Range messages (the URDF frame); when absent <board name>_link");
    frame_id_ = p.optionalString("frame_id", base + "_link");
    p.describe("conversion_time", "[s] wait after a ranging command before its result is read");
    conversion_time_ = p.optionalDouble("conversion_time", srf02::kConversionTime);
    p.requireInRange("conversion_time", conversion_time_, srf02::kConversionTime, 1.0);
    p.describe("field_of_view", "[rad] beam width reported in the Range messages");
    fov_ = p.optionalDouble("field_of_view", srf02::kFieldOfView);
    p.requireInRange("field_of_view", fov_, 0.01, 3.14);
  }

  void init(BoardContext& ctx) override {
    dev_ = openI2cDevice(i2c_);
    range_pub_ = ctx.pnh.advertise<sensor_msgs::Range>("range", 1, true);
    state_pub_ = ctx.pnh.advertise<SRF02State>("state", 1, true);
  }

  void check(BoardContext& /*ctx*/, CheckReport& report) override {
    I2cDevice dev;
    std::vector<uint8_t> raw;
    if (!checkI2cIdentity(i2c_, srf02::kRegRevision, srf02::kResultSize, dev, raw, report)) return;
    if (raw[0] == srf02::kBusy)
      report.warn("identity", "SRF02 software revision", "0xFF: ranging in progress",
                  "another master is ranging with it (is the product running?); run the doctor again");
    else
      report.ok("identity", "SRF02 software revision", "revision " + std::to_string(raw[0]));
  }

  bool service() override {
    auto addr_lock = dev_.bus->lockAddress(dev_.address);
    std::string err;
    const ros::Time now = ros::Time::now();
    if (!started_.isZero()) {
      if ((now - started_).toSec() < conversion_time_) return true;  // converting: nothing to ask yet
      std::vector<uint8_t> raw;
      if (dev_.bus->readRegisters(dev_.address, srf02::kRegRevision, srf02::kResultSize, raw, err) !=
          transport::I2cStatus::kOk) {
        started_ = ros::Time();  // start over: the ranging may have been lost with the board
        fail(err);
        return false;
      }
      const auto r = srf02::decodeResult(raw);
      if (r.kind == srf02::ResultKind::kBusy) {
        std::lock_guard lk(mutex_);
        ++busy_reads_;
        return true;  // it answered; the result comes on a later call
      }
      const ros::Time pinged = started_;
      started_ = ros::Time();
      if (r.kind == srf02::ResultKind::kInvalid) {
        std::lock_guard lk(mutex_);
        ++garbled_;
        fail("garbled result (range beyond 16 m)");
        return false;
      }
      publish(r, pinged);
    }
    if (dev_.bus->writeRegisters(dev_.address, srf02::kRegCommand, {srf02::kCmdRangeCm}, err) !=
        transport::I2cStatus::kOk) {
      fail(err);
      return false;
    }
    started_ = ros::Time::now();
    return true;
  }

  void halt() override { started_ = ros::Time(); }  // nothing moves; restart ranging cleanly

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    diagnoseI2c(dev_, stat);
    std::lock_guard lk(mutex_);
    stat.add("busy reads", busy_reads_);
    stat.add("garbled reads", garbled_);
    stat.add("ranges", ranges_);
  }

 private:
  void publish(const srf02::Result& r, const ros::Time& pinged) {
    const ros::Time now = ros::Time::now();
    sensor_msgs::Range::Ptr m(new sensor_msgs::Range);
    m->header.stamp = pinged;
    m->header.frame_id = frame_id_;
    m->radiation_type = sensor_msgs::Range::ULTRASOUND;
    m->field_of_view = static_cast<float>(fov_);
    m->min_range = static_cast<float>(srf02::kMinRangeM);
    m->max_range = static_cast<float>(srf02::kMaxRangeM);
    m->range = r.range_cm == 0 ? std::numeric_limits<float>::infinity()  // REP-117: no echo
                               : static_cast<float>(srf02::centimetresToMetres(r.range_cm));
    range_pub_.publish(m);
    SRF02State::Ptr s(new SRF02State);
    s->header.stamp = now;
    s->address = dev_.address;
    s->revision = r.revision;
    s->range_cm = r.range_cm;
    std::lock_guard lk(mutex_);
    ++ranges_;
    s->busy_reads = busy_reads_;
    state_pub_.publish(s);
  }

  I2cConfig i2c_;
  I2cDevice dev_;
  std::string frame_id_;
  double conversion_time_ = srf02::kConversionTime;
  double fov_ = srf02::kFieldOfView;
  ros::Time started_;  // when the pending ranging was commanded; zero = none pending
  ros::Publisher range_pub_, state_pub_;
  robot_core::PriorityInheritanceMutex mutex_;
  uint32_t busy_reads_ = 0;
  unsigned long garbled_ = 0, ranges_ = 0;
};

}  // namespace hcl_drivers

HCL_EXPORT_BOARD(SRF02,
                 "SRF02 I2C ultrasonic ranger (two-phase ranging, sensor_msgs/Range in metres).")
