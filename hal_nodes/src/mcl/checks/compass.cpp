#include "hal_nodes/mcl/checks/compass.h"

#include "hal_nodes/mcl/clusters.h"

#include <algorithm>
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
  // Innovation against the cloud's prior heading: the circular mean of the offsets from the
  // reading, squared, over the reading's variance plus the cloud's circular variance (a cloud
  // turned round, split across +-pi, has a mean offset of pi, not 0).
  const HeadingSpread prior = headingSpread(set, yaw_);
  nis_ = -1.0;
  if (prior.weight > 0.0) {
    const double r = prior.resultant;
    const double var = r > 0.0 ? -2.0 * std::log(std::min(r, 1.0)) : 1e6;  // the wrapped normal's
    nis_ = prior.mean * prior.mean / (sigma_ * sigma_ + var);
  }
  for (std::size_t i = 0; i < set.size(); ++i) set.w[i] *= tempered(likelihood(set.theta[i]));
}

bool Compass::innovation(double* nis) const {
  if (nis_ < 0.0) return false;
  *nis = nis_;
  return true;
}

bool Compass::redraw(ParticleSet& set, const StepContext& ctx, double fraction) {
  if (!(sigma_ > 0.0)) return false;  // no reading yet
  // A systematic share of the set (every k-th particle): the others keep their heading, so a
  // compass disturbed for a while (motors) is outweighed again once it reads true.
  const std::size_t n = set.size();
  const auto m = static_cast<std::size_t>(std::round(std::clamp(fraction, 0.0, 1.0) * static_cast<double>(n)));
  if (m == 0) return false;
  const double step = static_cast<double>(n) / static_cast<double>(m);
  for (std::size_t k = 0; k < m; ++k) {
    const auto i = std::min(n - 1, static_cast<std::size_t>(static_cast<double>(k) * step));
    set.theta[i] = wrapAngle(yaw_ + sigma_ * ctx.rng->gaussian());
  }
  nis_ = -1.0;
  return true;
}

}  // namespace hal_nodes::mcl
