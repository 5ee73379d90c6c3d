#include "hal_nodes/mcl/motion/motion_model.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace hal_nodes::mcl {

void MotionModel::validate() const {
  const std::pair<const char*, double> fields[] = {
      {"trans_per_trans", trans_per_trans}, {"trans_per_rot", trans_per_rot}, {"lateral_per_trans", lateral_per_trans},
      {"rot_per_trans", rot_per_trans},     {"rot_per_rot", rot_per_rot},     {"slip_trans", slip_trans},
      {"slip_rot", slip_rot}, {"slip_accel", slip_accel}, {"slip_margin", slip_margin}};
  for (const auto& f : fields)
    if (!(f.second >= 0.0) || !std::isfinite(f.second))
      throw std::invalid_argument(std::string(f.first) + " = " + std::to_string(f.second) + ": must be >= 0");
  if (!(slip_probability >= 0.0 && slip_probability <= 1.0))
    throw std::invalid_argument("slip_probability = " + std::to_string(slip_probability) + ": must be in [0, 1]");
}

void MotionModel::apply(ParticleSet& set, const Pose2D& d, Rng& rng, bool slipping) const {
  const double ads = std::hypot(d.x, d.y), adt = std::fabs(d.theta);
  const double s_trans = trans_per_trans * ads + trans_per_rot * adt;
  const double s_lat = lateral_per_trans * ads;
  const double s_rot = rot_per_trans * ads + rot_per_rot * adt;
  const std::size_t n = set.size();
  double* px = set.x.data();
  double* py = set.y.data();
  double* pt = set.theta.data();
  // Slips the odometry did not see: a heavy tail on a slip_probability share of the particles.
  const bool unseen_slips = !slipping && slip_probability > 0.0 && (ads > 0.0 || adt > 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    double ds = d.x + s_trans * rng.gaussian();
    const double dl = d.y + s_lat * rng.gaussian();
    double dt = d.theta + s_rot * rng.gaussian();
    if (unseen_slips && rng.uniform() < slip_probability) {
      // A slipping wheel turns without moving the robot: the robot went less far than the
      // encoders say (half-normal loss of travel), and its heading is disturbed.
      ds -= std::copysign(std::fabs(slip_trans * rng.gaussian()), d.x);
      dt += slip_rot * rng.gaussian();
    }
    if (slipping) dt += slip_rot * rng.gaussian();  // travel already limited by the odometry
    // Mid-point integration of the arc.
    const double a = pt[i] + 0.5 * dt;
    const double c = std::cos(a), s = std::sin(a);
    px[i] += c * ds - s * dl;
    py[i] += s * ds + c * dl;
    pt[i] = wrapAngle(pt[i] + dt);
  }
}

}  // namespace hal_nodes::mcl
