// Rangers: every distance sensor of the robot (SRF02 ultrasound, SHARP infrared), each read
// from its board as sensor_msgs/Range and published filtered on ~<name>
// (/hal/rangers/<name>) in the ranger's URDF frame. The filter (range_filter.h) removes
// nonsense values, peaks and noise; only new board readings enter it. A stale ranger
// publishes nothing and is named in the unavailability reason.
//
// Parameters: read and described in configure() (the table: hal_nodes/PARAMETERS.md, make docs).
#include <sensor_msgs/Range.h>

#include <cmath>

#include "hal_nodes/device_nodelet.h"
#include <robot_core/params.h>
#include "hal_nodes/devices/rangers/range_filter.h"

namespace hal_nodes {

class RangersDevice : public Device {
 public:
  void configure(const robot_core::Params& params) override {
    params.describe("max_input_age", "[s] a ranger whose newest board reading is older is stale");
    max_input_age_ = params.optionalDouble("max_input_age", 0.5);
    params.requirePositive("max_input_age", max_input_age_);
    const RangeFilterConfig defaults = readFilter(params, RangeFilterConfig(), "; every ranger's default");
    rangers_.clear();
    params.describe("rangers", "the distance sensors, by name: each published filtered on ~<name>");
    for (const auto& name : params.requireBlockNames("rangers")) {
      const robot_core::Params p = params.block("rangers/" + name);
      Ranger r;
      r.name = name;
      r.filter = RangeFilter(readFilter(p, defaults, "; this ranger's, else the device's"));
      p.describe("frame_id", "output frame ('': the board message's frame_id)");
      r.frame_id = p.optionalString("frame_id", "");
      p.describe("min_range", "[m] overrides the board's minimum range (< 0: the message's)");
      r.min_range = p.optionalDouble("min_range", -1.0);
      p.describe("max_range", "[m] overrides the board's maximum range (<= 0: the message's)");
      r.max_range = p.optionalDouble("max_range", -1.0);
      p.describe("topic", "the board's Range topic in (/hcl/<board>/range/<name>)");
      r.topic = p.requireString("topic");
      rangers_.push_back(std::move(r));
    }
  }

  void init(DeviceContext& ctx) override {
    for (Ranger& r : rangers_) {
      r.input = addInput<sensor_msgs::Range>(ctx.nh, r.topic, r.name, Wake::kOnArrival);
      r.pub = ctx.pnh.advertise<sensor_msgs::Range>(r.name, 5);
    }
  }

  void refresh() override {
    std::string stale;
    for (auto& r : rangers_) {
      const auto m = r.input->fresh(max_input_age_);
      if (!m) {
        if (r.filter.value()) r.filter.reset();  // do not mix old readings with new ones later
        stale += (stale.empty() ? "" : ", ") + r.name;
        continue;
      }
      if (m->header.stamp == r.last_stamp && !r.last_stamp.isZero()) continue;  // no new reading
      r.last_stamp = m->header.stamp;
      const double lo = r.min_range >= 0.0 ? r.min_range : m->min_range;
      const double hi = r.max_range > 0.0 ? r.max_range : m->max_range;
      const auto out = r.filter.add(m->range, lo, hi);
      if (!out) continue;
      sensor_msgs::Range o = *m;
      if (!r.frame_id.empty()) o.header.frame_id = r.frame_id;
      o.min_range = static_cast<float>(lo);
      o.max_range = static_cast<float>(hi);
      o.range = static_cast<float>(*out);
      r.pub.publish(o);
    }
    if (stale.empty()) setAvailable();
    else setUnavailable("no fresh readings from ranger(s): " + stale);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    for (const auto& r : rangers_) {
      stat.add("ranger " + r.name + " nonsense readings dropped", r.filter.nonsense());
      const auto v = r.filter.value();
      stat.addf("ranger " + r.name + " range [m]", "%.3f", v ? *v : NAN);
    }
  }

 private:
  struct Ranger {
    std::string name, frame_id, topic;
    double min_range = -1.0, max_range = -1.0;
    RangeFilter filter;
    std::shared_ptr<LatestValue<sensor_msgs::Range>> input;
    ros::Publisher pub;
    ros::Time last_stamp;
  };

  // The filter's settings (range_filter.h); `whose` ends each meaning (the defaults or one ranger's).
  static RangeFilterConfig readFilter(const robot_core::Params& p, const RangeFilterConfig& d,
                                      const std::string& whose) {
    RangeFilterConfig c;
    p.describe("window", "readings whose median replaces a jump, odd 1..51" + whose);
    const int window = p.optionalInt("window", static_cast<int>(d.window));
    if (window < 1 || window % 2 == 0 || window > 51)
      throw robot_core::ParameterError("parameter " + p.qualified("window") + " = " + std::to_string(window) +
                                       ": must be odd, 1..51");
    c.window = static_cast<std::size_t>(window);
    p.describe("smoothing", "weight of the newest value in the moving average (1: no smoothing)" + whose);
    c.smoothing = p.optionalDouble("smoothing", d.smoothing);
    p.requireInRange("smoothing", c.smoothing, 1e-3, 1.0);
    p.describe("step", "[m] a reading further than this from the trend is a jump" + whose);
    c.step = p.optionalDouble("step", d.step);
    p.requirePositive("step", c.step);
    p.describe("nearer_at_once", "a jump to a nearer range passes at once (collision guards)" + whose);
    c.nearer_at_once = p.optionalBool("nearer_at_once", d.nearer_at_once);
    return c;
  }

  std::vector<Ranger> rangers_;
  double max_input_age_ = 0.5;
};

}  // namespace hal_nodes

HAL_EXPORT_DEVICE(RangersDevice, Rangers,
                  "Rangers: filtered sensor_msgs/Range per ranger (nonsense, peaks and noise removed).")
