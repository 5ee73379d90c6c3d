#include "hal_nodes/devices/beacons/beacon_equation.h"

#include <cmath>

namespace hal_nodes {

double speedOfSound(double t) { return 331.3 * std::sqrt(1.0 + t / 273.15); }

double BeaconEquation::beaconOffset(int id) const {
  return (id >= 0 && static_cast<std::size_t>(id) < beacon_offsets.size()) ? beacon_offsets[id] : 0.0;
}

double BeaconEquation::distance(int id, double delta_s) const {
  return scale * speedOfSound(temperature) * delta_s + offset + beaconOffset(id);
}

LineFit fitLine(const std::vector<double>& x, const std::vector<double>& y) {
  LineFit f;
  if (x.size() != y.size()) {
    f.why = "the lists differ in length";
    return f;
  }
  const double n = static_cast<double>(x.size());
  if (x.size() < 2) {
    f.why = "at least two pairs are needed";
    return f;
  }
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i])) {
      f.why = "a value is not finite";
      return f;
    }
    mx += x[i];
    my += y[i];
  }
  mx /= n;
  my /= n;
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  if (sxx <= 1e-12 * (1.0 + mx * mx)) {
    f.why = "the deltas must not all be equal";
    return f;
  }
  f.slope = sxy / sxx;
  f.intercept = my - f.slope * mx;
  double ss = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double r = y[i] - (f.slope * x[i] + f.intercept);
    ss += r * r;
  }
  f.rms = std::sqrt(ss / n);
  f.ok = true;
  return f;
}

LineFit fitEquation(BeaconEquation& eq, const std::vector<double>& delta_s, const std::vector<double>& distance,
                    const std::vector<int>& ids) {
  if (!ids.empty() && ids.size() != distance.size()) {
    LineFit f;
    f.why = "beacon_id must be empty or as long as distance";
    return f;
  }
  std::vector<double> y(distance);
  for (std::size_t i = 0; i < ids.size(); ++i) y[i] -= eq.beaconOffset(ids[i]);
  LineFit f = fitLine(delta_s, y);
  if (!f.ok) return f;
  if (f.slope <= 0.0) {
    f.ok = false;
    f.why = "the fitted speed is not positive: check the pairs";
    return f;
  }
  eq.scale = f.slope / speedOfSound(eq.temperature);
  eq.offset = f.intercept;
  return f;
}

}  // namespace hal_nodes
