// The compass (heading) as a checking input:
//   p(yaw | pose) = (1 - outlier) * N(wrap(theta - yaw); sigma) + outlier / (2 pi)
// sigma from the measurement's variance when it has one, else ~std. A compass near motors is
// disturbed in bursts, hence the outlier term and a reliability below 1 in the configs, and a
// minimum interval between applied readings (successive readings are not independent).
// A heading far outside the cloud weighs every particle at the outlier floor, so it cannot move
// the cloud: the filter then watches the compass's own innovations, and when they say "wrong"
// for a window while the beacons agree, redraw() gives part of the set the compass's heading.
#pragma once

#include "hal_nodes/mcl/input.h"

namespace hal_nodes::mcl {

struct CompassConfig {
  double std = 0.05;                 // [rad]
  bool use_measurement_variance = true;
  double outlier_probability = 0.1;
  double reliability = 0.5;
  double min_interval = 0.1;         // [s] between applied readings
};

class Compass : public CheckingInput {
 public:
  explicit Compass(const CompassConfig& cfg);
  bool addHeading(double stamp, double yaw, double variance = 0.0);  // false: rejected
  bool ready(const StepContext&) const override { return pending_; }
  void check(ParticleSet& set, const StepContext& ctx) override;
  void clear() override { pending_ = false; }
  bool measuresHeading() const override { return true; }
  bool innovation(double* nis) const override;
  bool redraw(ParticleSet& set, const StepContext& ctx, double fraction) override;
  // The likelihood of one heading (exposed for tests).
  double likelihood(double theta) const;

 private:
  CompassConfig cfg_;
  bool pending_ = false;
  double yaw_ = 0.0, sigma_ = 0.0, last_applied_ = -1e300;
  double nis_ = -1.0;  // of the reading just applied (-1: none)
};

}  // namespace hal_nodes::mcl
