#include "hal_nodes/devices/odometry/wheel_pair.h"

#include <cmath>

namespace hal_nodes {

OdometryIncrement WheelPairModel::increment(double left_ticks, double right_ticks) const {
  const double l = left_m_per_tick * left_ticks;
  const double r = right_m_per_tick * right_ticks;
  OdometryIncrement inc;
  inc.ds = 0.5 * (l + r);
  inc.dtheta = (r - l) / track_width;
  inc.var_ds = distance_noise * distance_noise * std::abs(inc.ds);
  inc.var_dtheta = heading_noise * heading_noise * std::abs(inc.ds) + rotation_noise * rotation_noise * std::abs(inc.dtheta);
  return inc;
}

void IncrementFusion::add(const OdometryIncrement& inc, double weight) {
  sum_.ds += weight * inc.ds;
  sum_.dtheta += weight * inc.dtheta;
  sum_.var_ds += weight * inc.var_ds;
  sum_.var_dtheta += weight * inc.var_dtheta;
  weight_ += weight;
}

OdometryIncrement IncrementFusion::result() const {
  OdometryIncrement out;
  if (weight_ <= 0.0) return out;
  out.ds = sum_.ds / weight_;
  out.dtheta = sum_.dtheta / weight_;
  out.var_ds = sum_.var_ds / weight_;
  out.var_dtheta = sum_.var_dtheta / weight_;
  return out;
}

}  // namespace hal_nodes
