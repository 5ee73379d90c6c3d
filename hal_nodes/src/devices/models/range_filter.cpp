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
  window_.push_back(range);
  while (window_.size() > config_.window) window_.pop_front();
  std::vector<double> sorted(window_.begin(), window_.end());
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median = sorted[sorted.size() / 2];
  if (!output_ || !std::isfinite(median) || !std::isfinite(*output_) || std::abs(median - *output_) > config_.step) {
    output_ = median;
  } else {
    output_ = *output_ + config_.smoothing * (median - *output_);
  }
  return output_;
}

}  // namespace hal_nodes
