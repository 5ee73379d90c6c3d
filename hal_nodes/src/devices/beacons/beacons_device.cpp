// Beacons: the beacon receiver's raw times of flight (hcl_drivers/BeaconDelta events: one per
// beacon transmit slot, so they are queued, not sampled) become distances with variance,
// published as hal_nodes/BeaconRange on ~ranges (/hal/beacons/ranges). The equation
// (beacon_equation.h) can be changed while running (~set_equation) and fitted from
// externally measured distances (~fit_equation, least squares); the current values are
// mirrored into the ~temperature, ~scale, ~offset, ~beacon_offsets parameters.
// Distances outside [~min_range, ~max_range] are outliers (no line of sight, echoes): dropped
// and counted.
//
// Parameters: read and described in configure() (the table: hal_nodes/PARAMETERS.md, make docs).
#include <hal_nodes/BeaconRange.h>
#include <hal_nodes/FitBeaconEquation.h>
#include <hal_nodes/SetBeaconEquation.h>
#include <hcl_drivers/BeaconDelta.h>

#include <atomic>
#include <cmath>
#include <deque>
#include <mutex>
#include <optional>

#include "hal_nodes/device_nodelet.h"
#include "hal_nodes/devices/beacons/beacon_equation.h"
#include <robot_core/params.h>

namespace hal_nodes {

class BeaconsDevice : public Device {
 public:
  void configure(const robot_core::Params& params) override {
    BeaconEquation eq;
    params.describe("temperature", "[degC] the air's temperature, for the speed of sound (mirrored while running)");
    eq.temperature = params.optionalDouble("temperature", 20.0);
    params.requireInRange("temperature", eq.temperature, -40.0, 80.0);
    params.describe("scale", "the equation's scale: humidity, the receiver's clock (mirrored while running)");
    eq.scale = params.optionalDouble("scale", 1.0);
    params.requireInRange("scale", eq.scale, 0.5, 2.0);
    params.describe("offset", "[m] the equation's fixed delays: trigger, receiver threshold (mirrored while running)");
    eq.offset = params.optionalDouble("offset", 0.0);
    params.requireInRange("offset", eq.offset, -1.0, 1.0);
    params.describe("beacon_offsets", "[m] added to each beacon's distance, by beacon id (mirrored while running)");
    eq.beacon_offsets = params.optionalDoubleList("beacon_offsets");
    equation_ = eq;
    params.describe("range_noise", "[m] the distance's std independent of the distance");
    noise_ = params.optionalDouble("range_noise", 0.02);
    params.requirePositive("range_noise", noise_);
    params.describe("range_noise_relative", "[m/m] the distance's std per metre of distance");
    noise_rel_ = params.optionalDouble("range_noise_relative", 0.01);
    params.requireInRange("range_noise_relative", noise_rel_, 0.0, 1.0);
    params.describe("min_range", "[m] shorter distances are outliers: dropped and counted");
    min_range_ = params.optionalDouble("min_range", 0.05);
    params.describe("max_range", "[m] longer distances are outliers (no line of sight, echoes): dropped and counted");
    max_range_ = params.optionalDouble("max_range", 4.0);
    params.requireInRange("min_range", min_range_, 0.0, 10.0);
    params.requireInRange("max_range", max_range_, min_range_ + 1e-3, 20.0);
    params.describe("frame_id", "the receiver's frame");
    frame_id_ = params.optionalString("frame_id", "beacon_receiver");
    params.describe("max_input_age", "[s] no delta for longer: unavailable");
    max_input_age_ = params.optionalDouble("max_input_age", 1.0);
    params.requirePositive("max_input_age", max_input_age_);
    params.describe("delta", "the receiver's times of flight in (hcl_drivers/BeaconDelta, /hcl/<board>/delta)");
    topic_ = params.requireString("delta");
  }

  void init(DeviceContext& ctx) override {
    using namespace hcl_drivers;  // the boards' messages
    pnh_.emplace(ctx.pnh);
    const BeaconEquation eq = equation_;  // as configured, before a service can change it
    latest_ = addInput<BeaconDelta>(ctx.nh, topic_, "delta");  // for its age on /diagnostics
    events_sub_ = ctx.nh.subscribe<BeaconDelta>(topic_, 100, [this](const BeaconDelta::ConstPtr& m) {
      std::lock_guard<std::mutex> lk(queue_mutex_);
      queue_.push_back(m);
      if (queue_.size() > 200) {  // refresh stalled: keep the newest, count the rest
        queue_.pop_front();
        ++overflow_;
      }
    });
    pub_ = ctx.pnh.advertise<BeaconRange>("ranges", 50);
    set_srv_ = ctx.pnh.advertiseService("set_equation", &BeaconsDevice::onSet, this);
    fit_srv_ = ctx.pnh.advertiseService("fit_equation", &BeaconsDevice::onFit, this);
    mirror(eq);
  }

  void refresh() override {
    std::deque<hcl_drivers::BeaconDelta::ConstPtr> batch;
    {
      std::lock_guard<std::mutex> lk(queue_mutex_);
      batch.swap(queue_);
    }
    BeaconEquation eq;
    {
      std::lock_guard<std::mutex> lk(eq_mutex_);
      eq = equation_;
    }
    for (const auto& m : batch) {
      const double d = eq.distance(m->beacon_id, 1e-6 * m->delta_us);
      if (!std::isfinite(d) || d < min_range_ || d > max_range_) {
        ++outliers_;
        continue;
      }
      BeaconRange r;
      r.header.stamp = m->header.stamp;
      r.header.frame_id = frame_id_;
      r.beacon_id = m->beacon_id;
      r.range = d;
      const double sd = noise_ + noise_rel_ * d;
      r.variance = sd * sd;
      pub_.publish(r);
      ++published_;
    }
    if (latest_->age() > max_input_age_)
      setUnavailable("no beacon delta for " + std::to_string(latest_->age()) + " s (receiver silent or beacons off)");
    else
      setAvailable();
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    std::lock_guard<std::mutex> lk(eq_mutex_);
    stat.add("ranges published", published_.load());
    stat.add("outliers dropped", outliers_.load());
    stat.add("queue overflows", overflow_.load());
    stat.addf("equation", "%.5f * c(%.1f degC) * delta %+.4f m", equation_.scale, equation_.temperature, equation_.offset);
  }

 private:
  bool onSet(SetBeaconEquation::Request& req, SetBeaconEquation::Response& res) {
    if (!std::isfinite(req.temperature) || req.temperature < -40 || req.temperature > 80 || !(req.scale > 0.5 && req.scale < 2.0) ||
        !std::isfinite(req.offset) || std::abs(req.offset) > 1.0) {
      res.success = false;
      res.message = "rejected: temperature must be -40..80 degC, scale 0.5..2, |offset| <= 1 m";
      return true;
    }
    BeaconEquation eq;
    {
      std::lock_guard<std::mutex> lk(eq_mutex_);
      equation_.temperature = req.temperature;
      equation_.scale = req.scale;
      equation_.offset = req.offset;
      if (!req.beacon_offsets.empty()) equation_.beacon_offsets = req.beacon_offsets;
      eq = equation_;
    }
    mirror(eq);
    res.success = true;
    res.message = "equation set";
    ROS_INFO("beacons: equation set: scale %.5f, temperature %.1f degC, offset %.4f m", eq.scale, eq.temperature, eq.offset);
    return true;
  }

  bool onFit(FitBeaconEquation::Request& req, FitBeaconEquation::Response& res) {
    std::vector<double> delta_s;
    for (double us : req.delta_us) delta_s.push_back(1e-6 * us);
    std::vector<int> ids(req.beacon_id.begin(), req.beacon_id.end());
    BeaconEquation eq;
    {
      std::lock_guard<std::mutex> lk(eq_mutex_);
      eq = equation_;
    }
    const LineFit f = fitEquation(eq, delta_s, req.distance, ids);
    res.success = f.ok;
    if (!f.ok) {
      res.message = "fit failed: " + f.why;
      return true;
    }
    res.scale = eq.scale;
    res.offset = eq.offset;
    res.rms_residual = f.rms;
    res.message = req.apply ? "fitted and applied" : "fitted (not applied)";
    if (req.apply) {
      {
        std::lock_guard<std::mutex> lk(eq_mutex_);
        equation_.scale = eq.scale;
        equation_.offset = eq.offset;
      }
      mirror(eq);
      ROS_INFO("beacons: fitted equation applied: scale %.5f, offset %.4f m, rms %.4f m", eq.scale, eq.offset, f.rms);
    }
    return true;
  }

  void mirror(const BeaconEquation& eq) {
    pnh_->setParam("temperature", eq.temperature);
    pnh_->setParam("scale", eq.scale);
    pnh_->setParam("offset", eq.offset);
    pnh_->setParam("beacon_offsets", eq.beacon_offsets);
  }

  std::optional<ros::NodeHandle> pnh_;  // from init(): constructing a handle needs ros::init (a checker has none)
  std::mutex eq_mutex_;
  BeaconEquation equation_;
  std::mutex queue_mutex_;
  std::deque<hcl_drivers::BeaconDelta::ConstPtr> queue_;
  std::shared_ptr<LatestValue<hcl_drivers::BeaconDelta>> latest_;
  ros::Subscriber events_sub_;
  ros::Publisher pub_;
  ros::ServiceServer set_srv_, fit_srv_;
  std::string frame_id_, topic_;
  double noise_ = 0.02, noise_rel_ = 0.01, min_range_ = 0.05, max_range_ = 4.0, max_input_age_ = 1.0;
  std::atomic<unsigned long> published_{0}, outliers_{0}, overflow_{0};
};

}  // namespace hal_nodes

HAL_EXPORT_DEVICE(BeaconsDevice, Beacons,
                  "Beacons: raw times of flight to distances with variance; runtime-settable, fittable equation.")
