#include "robot_sim/world/ranger_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace robot_sim {

double trueRange(const RangerConfig& r, const Pose2D& robot, const TableGeometry& table,
                 const std::vector<Circle>& obstacles) {
  const double c = std::cos(robot.theta), s = std::sin(robot.theta);
  const double x = robot.x + c * r.mount.x - s * r.mount.y;
  const double y = robot.y + s * r.mount.x + c * r.mount.y;
  const double a = robot.theta + r.mount.theta;
  // The nearest echo anywhere in the cone, as the localization expects it; nothing beyond the
  // sensor's range comes back.
  const double range = table.coneRange(x, y, a, r.beam_width, obstacles);
  return range <= r.max_range ? range : std::numeric_limits<double>::infinity();
}

double noisyRange(const RangerConfig& r, double true_range, Rng& rng) {
  if (!std::isfinite(true_range)) return true_range;
  const double m = true_range + r.bias + rng.gaussian(r.noise_std + r.noise_rel * true_range);
  if (m > r.max_range) return std::numeric_limits<double>::infinity();
  return std::max(r.min_range, m);
}

}  // namespace robot_sim
