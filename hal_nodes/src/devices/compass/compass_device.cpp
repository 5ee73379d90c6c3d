// Compass: the module's bearing (hcl_drivers/Bearing, degrees clockwise from the module's
// north, as the CMPS03 reports it) becomes a REP-103 heading: the yaw of base_link in `map`,
// counter-clockwise from the table's x axis. Calibration: ~north_yaw is the map yaw at which
// the module reads 0 deg (measure it once on the table: it depends on the building), and
// ~mounting_clockwise says the module turns the usual way (false: mounted upside down).
//
// Parameters: read and described in configure() (the table: hal_nodes/PARAMETERS.md, make docs).
#include <hal_nodes/Heading.h>
#include <hcl_drivers/Bearing.h>

#include <cmath>

#include "hal_nodes/device_nodelet.h"
#include "hal_nodes/devices/odometry/pose_integrator.h"

namespace hal_nodes {

class CompassDevice : public Device {
 public:
  void configure(const robot_core::Params& params) override {
    params.describe("north_yaw", "[rad] the map yaw at which the module reads 0 deg (measured on the table)");
    north_yaw_ = params.requireDouble("north_yaw");
    params.requireInRange("north_yaw", north_yaw_, -2 * M_PI, 2 * M_PI);
    params.describe("mounting_clockwise", "the module turns the usual way (false: mounted upside down)");
    clockwise_ = params.optionalBool("mounting_clockwise", true);
    params.describe("variance", "[rad^2] the published heading's variance (0.0025: about 3 deg std)");
    variance_ = params.optionalDouble("variance", 0.0025);
    params.requirePositive("variance", variance_);
    params.describe("max_input_age", "[s] no bearing for longer: unavailable");
    max_input_age_ = params.optionalDouble("max_input_age", 0.5);
    params.requirePositive("max_input_age", max_input_age_);
    params.describe("frame_id", "the published heading's frame");
    frame_id_ = params.optionalString("frame_id", "map");
    params.describe("bearing", "the module's bearing in (hcl_drivers/Bearing, /hcl/<board>/bearing)");
    bearing_topic_ = params.requireString("bearing");
  }

  void init(DeviceContext& ctx) override {
    using namespace hcl_drivers;  // the boards' messages
    bearing_ = addInput<Bearing>(ctx.nh, bearing_topic_, "bearing");
    pub_ = ctx.pnh.advertise<Heading>("heading", 1);
  }

  void refresh() override {
    const auto b = bearing_->fresh(max_input_age_);
    if (!b) {
      setUnavailable("no fresh compass bearing (age " + std::to_string(bearing_->age()) + " s)");
      return;
    }
    if (!std::isfinite(b->degrees) || b->degrees < 0.0 || b->degrees >= 360.0 + 1e-9) {
      ++bad_;
      setUnavailable("compass bearing out of 0..360 deg: " + std::to_string(b->degrees));
      return;
    }
    setAvailable();
    if (b->header.stamp == last_stamp_ && !last_stamp_.isZero()) return;  // nothing new
    last_stamp_ = b->header.stamp;
    Heading h;
    h.header.stamp = b->header.stamp;
    h.header.frame_id = frame_id_;
    const double rad = b->degrees * M_PI / 180.0;
    h.yaw = wrapAngle(clockwise_ ? north_yaw_ - rad : north_yaw_ + rad);
    h.variance = variance_;
    pub_.publish(h);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override { stat.add("bad bearings", bad_); }

 private:
  std::shared_ptr<LatestValue<hcl_drivers::Bearing>> bearing_;
  ros::Publisher pub_;
  ros::Time last_stamp_;
  std::string frame_id_, bearing_topic_;
  double north_yaw_ = 0.0, variance_ = 0.0025, max_input_age_ = 0.5;
  bool clockwise_ = true;
  unsigned long bad_ = 0;
};

}  // namespace hal_nodes

HAL_EXPORT_DEVICE(CompassDevice, Compass,
                  "Compass: module bearing to a REP-103 heading in map, with calibration offset.")
