// Our robot's outline seen from above: a polygon in base_link (REP-103), the one shape used for
// collisions with the borders and the opponent, for pushing game elements and for locating
// bumper contacts (which bumper closes depends on where on the outline the contact is).
#pragma once

#include <vector>

#include "robot_sim/world/config.h"
#include "robot_sim/world/table_geometry.h"

namespace robot_sim {

// Where the outline meets (or comes nearest to) an obstacle.
struct Contact {
  double clearance = 0.0;  // free distance [m], negative: overlap depth
  Point2D point;           // on the outline, map frame
  Point2D normal;          // unit, out of the outline at `point` (map): towards an obstacle outside
};

class Footprint {
 public:
  // `points`: the polygon's vertices in base_link, in order (either sense), >= 3, not
  // self-intersecting, base_link's origin inside. Throws ConfigError naming what is wrong.
  explicit Footprint(std::vector<Point2D> points);
  // A regular polygon with `n` vertices on the circle of `radius`, one at +x.
  static std::vector<Point2D> regular(double radius, int n);

  const std::vector<Point2D>& points() const { return points_; }
  double boundingRadius() const { return bounding_radius_; }
  // How far the outline reaches along the base_link direction `angle` (its support distance).
  double reach(double angle) const;
  // The vertices placed at `pose` on the table (map frame).
  std::vector<Point2D> placed(const Pose2D& pose) const;

 private:
  std::vector<Point2D> points_;
  double bounding_radius_ = 0.0;
};

// Outline `poly` (map) against the inside of the table [0, length] x [0, width]: the nearest
// border. A flat side against a border touches along it: the contact point is the middle of
// the vertices within 1 mm of the deepest one.
Contact borderContact(const std::vector<Point2D>& poly, double length, double width);

// Outline `poly` (map) against a circle; a circle whose centre is inside counts as overlapping
// by its distance to the outline plus its radius.
Contact circleContact(const std::vector<Point2D>& poly, const Circle& c);

// The robot's configured outline, or the regular 32-gon on its radius (within 0.5 % of it).
Footprint robotFootprint(const RobotConfig& robot);

bool insidePolygon(const std::vector<Point2D>& poly, double x, double y);

// Moves a circle overlapping the outline out of it, along the contact normal, until it just
// touches. True when it moved.
bool pushOut(const std::vector<Point2D>& poly, Circle& c);

}  // namespace robot_sim
