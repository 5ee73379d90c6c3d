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
  // A fan of rays: 1 for a narrow infrared beam, up to 9 across an ultrasonic cone.
  const int rays = r.beam_width < 0.1 ? 1 : std::min(9, 3 + 2 * static_cast<int>(r.beam_width / 0.2));
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < rays; ++i) {
    const double off = rays == 1 ? 0.0 : r.beam_width * (static_cast<double>(i) / (rays - 1) - 0.5);
    best = std::min(best, table.rayCast(x, y, a + off, r.max_range, obstacles));
  }
  return best;
}

double noisyRange(const RangerConfig& r, double true_range, Rng& rng) {
  if (!std::isfinite(true_range)) return true_range;
  const double m = true_range + rng.gaussian(r.noise_std + r.noise_rel * true_range);
  if (m > r.max_range) return std::numeric_limits<double>::infinity();
  return std::max(r.min_range, m);
}

}  // namespace robot_sim
