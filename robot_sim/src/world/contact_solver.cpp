#include "robot_sim/world/contact_solver.h"

#include <cmath>
#include <limits>

#include "robot_sim/world/diff_drive.h"

namespace robot_sim {

namespace {
constexpr double kTolerance = 1e-9;  // [m] overlap a push-out may leave (rounding)
constexpr int kPushIterations = 4;   // enough for a corner between a border and the opponent

// Every obstacle's contact with the outline at `pose`: the four borders, then each circle.
std::vector<Contact> contacts(const Footprint& f, const Pose2D& pose, const Obstacles& obs) {
  std::vector<Contact> out;
  out.reserve(4 + obs.circles.size());
  for (const Contact& c : f.borderContacts(pose, obs.table_length, obs.table_width)) out.push_back(c);
  for (const Circle& c : obs.circles) out.push_back(f.circleContact(pose, c));
  return out;
}

// Pushes `pose` out of every obstacle it overlaps more than `allowed` (per obstacle, from the
// pose before the step). False when the overlap cannot be undone within the iterations.
bool pushOut(const Footprint& f, Pose2D& pose, const std::vector<double>& allowed, const Obstacles& obs) {
  for (int i = 0; i < kPushIterations; ++i) {
    bool pushed = false;
    const std::vector<Contact> cs = contacts(f, pose, obs);
    for (std::size_t k = 0; k < cs.size(); ++k) {
      const double excess = -cs[k].clearance - allowed[k];
      if (excess <= kTolerance) continue;
      pose.x -= cs[k].normal.x * excess;
      pose.y -= cs[k].normal.y * excess;
      pushed = true;
      break;
    }
    if (!pushed) return true;
  }
  const std::vector<Contact> cs = contacts(f, pose, obs);
  for (std::size_t k = 0; k < cs.size(); ++k)
    if (-cs[k].clearance - allowed[k] > kTolerance) return false;
  return true;
}

// Ground travel of each wheel for the motion from `a` to `b` (forward along the mean heading).
void wheelTravel(const Pose2D& a, const Pose2D& b, double wheel_base, double& left, double& right) {
  const double dtheta = wrapAngle(b.theta - a.theta);
  const double heading = a.theta + 0.5 * dtheta;
  const double forward = (b.x - a.x) * std::cos(heading) + (b.y - a.y) * std::sin(heading);
  left = forward - 0.5 * wheel_base * dtheta;
  right = forward + 0.5 * wheel_base * dtheta;
}

bool stalled(double asked, double done) {
  if (std::abs(asked) < 1e-12) return false;
  return done / asked < 0.5;
}
}  // namespace

Contact nearestContact(const Footprint& f, const Pose2D& pose, const Obstacles& obs) {
  Contact best;
  best.clearance = std::numeric_limits<double>::infinity();
  for (const Contact& c : contacts(f, pose, obs))
    if (c.clearance < best.clearance) best = c;
  return best;
}

ResolvedMotion resolveMotion(const Footprint& f, const Pose2D& now, const Pose2D& next, const Obstacles& obs,
                             double wheel_base) {
  ResolvedMotion r;
  std::vector<double> allowed;
  for (const Contact& c : contacts(f, now, obs)) allowed.push_back(std::max(0.0, -c.clearance));
  // Wedged (no push-out frees the whole step): the step's translation alone, then its turn
  // alone, then nothing. A robot squeezed between two obstacles still slides out along them
  // when its wheels turn it a hair.
  Pose2D pose = next;
  if (!pushOut(f, pose, allowed, obs)) {
    pose = Pose2D{next.x, next.y, now.theta};
    if (!pushOut(f, pose, allowed, obs)) {
      pose = Pose2D{now.x, now.y, next.theta};
      if (!pushOut(f, pose, allowed, obs)) pose = now;
    }
  }
  r.cancelled = std::hypot(pose.x - next.x, pose.y - next.y) > kTolerance || pose.theta != next.theta;
  double ask_l, ask_r, did_l, did_r;
  wheelTravel(now, next, wheel_base, ask_l, ask_r);
  wheelTravel(now, pose, wheel_base, did_l, did_r);
  r.left_stalled = r.cancelled && stalled(ask_l, did_l);
  r.right_stalled = r.cancelled && stalled(ask_r, did_r);
  // Both wheels held: the robot does not creep along the obstacle on what little is left.
  r.pose = r.left_stalled && r.right_stalled ? now : pose;
  return r;
}

}  // namespace robot_sim
