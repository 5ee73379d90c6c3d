#include "robot_core/rate_meter.h"

#include <algorithm>
#include <cmath>

namespace robot_core {

RateMeter::RateMeter(double window_s) : window_(window_s) {}

void RateMeter::tick(double t, double busy_s) {
  ticks_.push_back({t, busy_s});
  trim(t);
}

void RateMeter::trim(double now) {
  // Keep at least two ticks so a slow loop still has a rate.
  while (ticks_.size() > 2 && now - ticks_.front().t > window_) ticks_.pop_front();
}

double RateMeter::rate() const {
  if (ticks_.size() < 2) return 0.0;
  const double span = ticks_.back().t - ticks_.front().t;
  return span > 0.0 ? static_cast<double>(ticks_.size() - 1) / span : 0.0;
}

double RateMeter::maxPeriodError(double expected_period) const {
  double worst = 0.0;
  for (std::size_t i = 1; i < ticks_.size(); ++i)
    worst = std::max(worst, std::fabs((ticks_[i].t - ticks_[i - 1].t) - expected_period));
  return worst;
}

double RateMeter::meanBusy() const {
  if (ticks_.empty()) return 0.0;
  double sum = 0.0;
  for (const auto& k : ticks_) sum += k.busy;
  return sum / static_cast<double>(ticks_.size());
}

double RateMeter::maxBusy() const {
  double worst = 0.0;
  for (const auto& k : ticks_) worst = std::max(worst, k.busy);
  return worst;
}

}  // namespace robot_core
