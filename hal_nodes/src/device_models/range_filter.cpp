#include "hal_nodes/devices/rangers/range_filter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace hal_nodes {

void RangeFilter::reset() {
  window_.clear();
  output_.reset();
}

std::optional<double> RangeFilter::add(double range, double min_range, double max_range, Verdict* verdict) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  Verdict v = Verdict::kAccepted;
  if (std::isnan(range) || range < 0.0 || (std::isfinite(range) && range < min_range)) {
    v = Verdict::kNonsense;
  } else if (range >= max_range) {
    v = Verdict::kNoEcho;
    range = kInf;
  }
  if (verdict) *verdict = v;
  if (v == Verdict::kNonsense) {
    ++nonsense_;
    return output_;
  }
  // A reading that continues the previous ones (within `step` of the last reading or of the
  // line through the last two) is no lone spike: it passes at once. The median would delay
  // it by window/2 readings, and a sweeping ranger (the robot turning beside a wall) would
  // then report the range of a direction it no longer looks in.
  bool continues = false;
  const double reach = config_.step * (1.0 + 1e-9);  // "within step", rounding aside
  if (std::isfinite(range) && !window_.empty() && std::isfinite(window_.back())) {
    const double r1 = window_.back();
    continues = std::abs(range - r1) <= reach;
    if (!continues && window_.size() >= 2 && std::isfinite(window_[window_.size() - 2]))
      continues = std::abs(range - (2.0 * r1 - window_[window_.size() - 2])) <= reach;
  }
  window_.push_back(range);
  while (window_.size() > config_.window) window_.pop_front();
  double value = range;
  const bool nearer = config_.nearer_at_once && std::isfinite(range) && output_ && range < *output_;
  if (!continues && !nearer) {  // a jump: a peak unless the median of the window confirms it
    std::vector<double> sorted(window_.begin(), window_.end());
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    value = sorted[sorted.size() / 2];
  }
  if (!output_ || !std::isfinite(value) || !std::isfinite(*output_) || std::abs(value - *output_) > config_.step) {
    output_ = value;
  } else {
    output_ = *output_ + config_.smoothing * (value - *output_);
  }
  return output_;
}

}  // namespace hal_nodes
