#include "hal_nodes/mcl/checks/rangers.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hal_nodes::mcl {

Rangers::Rangers(const std::vector<RangerConfig>& rangers, double reliability, std::shared_ptr<const TableModel> table)
    : CheckingInput("rangers", reliability), table_(std::move(table)) {
  if (!table_) throw std::invalid_argument("rangers: a table model is needed");
  if (!(reliability >= 0.0 && reliability <= 1.0)) throw std::invalid_argument("rangers: reliability must be in [0, 1]");
  for (const auto& r : rangers) {
    if (!(r.max_range > r.min_range && r.min_range >= 0.0))
      throw std::invalid_argument("ranger " + r.name + ": need 0 <= min_range < max_range");
    if (!(r.std > 0.0)) throw std::invalid_argument("ranger " + r.name + ": std must be > 0");
    if (!(r.short_probability >= 0.0 && r.short_probability < 1.0 && r.miss_probability > 0.0 && r.miss_probability <= 1.0))
      throw std::invalid_argument("ranger " + r.name + ": short_probability in [0, 1), miss_probability in (0, 1]");
    State s;
    s.cfg = r;
    rangers_.push_back(s);
  }
}

std::size_t Rangers::index(const std::string& name) const {
  for (std::size_t i = 0; i < rangers_.size(); ++i)
    if (rangers_[i].cfg.name == name) return i;
  throw std::out_of_range("rangers: no ranger named '" + name + "'");
}

bool Rangers::addRange(std::size_t k, double stamp, double range, double field_of_view) {
  State& s = rangers_.at(k);
  if (std::isnan(range) || !std::isfinite(stamp)) return false;
  if (stamp - s.last_applied < s.cfg.min_interval) return true;
  // REP 117: -inf is "nearer than the part can measure", +inf "nothing in range": the two
  // censored readings, information too (the HAL's range filter passes +inf on for that).
  s.range = std::isinf(range) ? (range < 0.0 ? s.cfg.min_range : s.cfg.max_range) : range;
  s.beam_width = s.cfg.beam_width >= 0.0 ? s.cfg.beam_width
                                          : (std::isfinite(field_of_view) ? std::clamp(field_of_view, 0.0, M_PI) : 0.0);
  s.last_applied = stamp;
  s.pending = true;
  return true;
}

bool Rangers::ready(const StepContext&) const {
  for (const auto& s : rangers_)
    if (s.pending) return true;
  return false;
}

void Rangers::clear() {
  for (auto& s : rangers_) s.pending = false;
}

double Rangers::likelihood(std::size_t k, const Pose2D& pose, double range, double beam_width) const {
  const RangerConfig& c = rangers_.at(k).cfg;
  const Pose2D sensor = compose(pose, {c.x, c.y, c.yaw});
  const double expected =
      std::min(table_->geometry().coneRange(sensor.x, sensor.y, sensor.theta, beam_width), c.max_range);
  if (range >= c.max_range * 0.999) return expected >= c.max_range * 0.999 ? 1.0 - c.short_probability : c.miss_probability;
  if (range <= c.min_range * 1.001) {  // "min_range or nearer": the chance the true distance is below it
    const double below = 0.5 * std::erfc((expected - c.min_range) / (c.std * std::sqrt(2.0)));
    return (1.0 - c.short_probability) * below + c.short_probability * c.min_range / c.max_range;
  }
  const double e = range - expected;
  return (1.0 - c.short_probability) * std::exp(-0.5 * e * e / (c.std * c.std)) / (c.std * std::sqrt(2.0 * M_PI)) +
         c.short_probability / c.max_range;
}

void Rangers::check(ParticleSet& set, const StepContext&) {
  for (std::size_t k = 0; k < rangers_.size(); ++k) {
    State& s = rangers_[k];
    if (!s.pending) continue;
    s.pending = false;
    for (std::size_t i = 0; i < set.size(); ++i)
      if (set.w[i] > 0.0) set.w[i] *= tempered(likelihood(k, {set.x[i], set.y[i], set.theta[i]}, s.range, s.beam_width));
  }
}

}  // namespace hal_nodes::mcl
