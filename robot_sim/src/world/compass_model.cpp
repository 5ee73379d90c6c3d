#include "robot_sim/world/compass_model.h"

#include <cmath>

namespace robot_sim {

namespace {
double wrap360(double d) {
  d = std::fmod(d, 360.0);
  return d < 0 ? d + 360.0 : d;
}
}  // namespace

double trueCompassDeg(const CompassConfig& c, double theta) {
  return wrap360(c.north_deg - theta * 180.0 / M_PI);  // clockwise from north
}

double noisyCompassDeg(const CompassConfig& c, double theta, Rng& rng) {
  return wrap360(trueCompassDeg(c, theta) + c.bias_deg + rng.gaussian(c.noise_std_deg));
}

}  // namespace robot_sim
