// The maneuver's curve: cubic Hermite segments joining the robot's start pose and a queue of
// checkpoints. At each node the curve passes through the point with a tangent vector shared by
// the segment that ends there and the one that starts there, so the path is C1 (position and
// first derivative continuous) at every checkpoint.
//
// Tangents: a checkpoint may fix its heading; by default the tangent points to the next
// checkpoint (the last one: along the incoming chord), the start node's tangent is the robot's
// heading, unless the robot faces away from the first checkpoint (more than 90 degrees off the
// chord): then the chord's direction, so the curve never loops out behind the goal. The tangent length is the shorter of the two adjacent chords, which keeps short
// segments from looping.
#pragma once

#include <vector>

#include "hal_nodes/driver/geometry.h"

namespace hal_nodes {
namespace driver {

struct Checkpoint {
  double x = 0.0;
  double y = 0.0;
  bool has_heading = false;  // true: the curve passes with this heading
  double heading = 0.0;      // [rad]
};

// One point of the sampled curve.
struct PathSample {
  double x = 0.0, y = 0.0;
  double heading = 0.0;  // tangent direction [rad]
  double s = 0.0;        // arc length from the start [m]
  double curvature = 0.0;  // [1/m], positive turning left
  int segment = 0;       // segment index: segment i ends at checkpoint i
};

class HermitePath {
 public:
  HermitePath() = default;
  // Start at `start` (its heading is the first tangent) and pass through every checkpoint.
  HermitePath(const Pose2D& start, const std::vector<Checkpoint>& checkpoints);

  int segments() const { return static_cast<int>(points_.size()) - 1; }
  bool empty() const { return segments() < 1; }
  // Position and first derivative (d/du) on segment i at u in [0, 1].
  Point2D position(int segment, double u) const;
  Point2D derivative(int segment, double u) const;
  Point2D secondDerivative(int segment, double u) const;
  const std::vector<Point2D>& nodes() const { return points_; }
  const std::vector<Point2D>& tangents() const { return tangents_; }

  // The curve as a polyline, points at most `step` metres apart along each chord (>= 8 per
  // segment), ending exactly on the last checkpoint.
  std::vector<PathSample> sample(double step) const;

 private:
  std::vector<Point2D> points_;    // start + checkpoints
  std::vector<Point2D> tangents_;  // d/du at each node
};

}  // namespace driver
}  // namespace hal_nodes
