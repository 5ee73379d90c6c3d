#include "hal_nodes/mcl/checks/compass.h"

#include <cmath>
#include <stdexcept>

namespace hal_nodes::mcl {

Compass::Compass(const CompassConfig& cfg) : CheckingInput("compass", cfg.reliability), cfg_(cfg) {
  if (!(cfg_.std > 0.0)) throw std::invalid_argument("compass: std must be > 0");
  if (!(cfg_.outlier_probability >= 0.0 && cfg_.outlier_probability < 1.0))
    throw std::invalid_argument("compass: outlier_probability must be in [0, 1)");
  if (!(cfg_.reliability >= 0.0 && cfg_.reliability <= 1.0)) throw std::invalid_argument("compass: reliability must be in [0, 1]");
  if (!(cfg_.min_interval >= 0.0)) throw std::invalid_argument("compass: min_interval must be >= 0");
}

bool Compass::addHeading(double stamp, double yaw, double variance) {
  if (!std::isfinite(yaw) || !std::isfinite(stamp)) return false;
  if (stamp - last_applied_ < cfg_.min_interval) return true;  // accepted, not yet independent
  yaw_ = wrapAngle(yaw);
  sigma_ = (cfg_.use_measurement_variance && variance > 0.0 && std::isfinite(variance)) ? std::sqrt(variance) : cfg_.std;
  last_applied_ = stamp;
  pending_ = true;
  return true;
}

double Compass::likelihood(double theta) const {
  const double e = wrapAngle(theta - yaw_);
  return (1.0 - cfg_.outlier_probability) * std::exp(-0.5 * e * e / (sigma_ * sigma_)) / (sigma_ * std::sqrt(2.0 * M_PI)) +
         cfg_.outlier_probability / (2.0 * M_PI);
}

void Compass::check(ParticleSet& set, const StepContext&) {
  if (!pending_) return;
  pending_ = false;
  for (std::size_t i = 0; i < set.size(); ++i) set.w[i] *= tempered(likelihood(set.theta[i]));
}

}  // namespace hal_nodes::mcl
