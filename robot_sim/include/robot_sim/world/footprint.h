// Our robot's outline seen from above, the one shape used for collisions with the borders and
// the opponent, for pushing game elements and for locating bumper contacts (which bumper
// closes depends on where on the outline the contact is): the configured polygon in base_link
// (REP-103), or a true circle about base_link when none is configured.
#pragma once

#include <array>
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
  // A polygon: `points` are its vertices in base_link, in order (either sense), >= 3, not
  // self-intersecting, base_link's origin inside. Throws ConfigError naming what is wrong.
  explicit Footprint(std::vector<Point2D> points);
  // A circle of `radius` about base_link's origin.
  static Footprint circle(double radius);
  // A regular polygon with `n` vertices on the circle of `radius`, one at +x.
  static std::vector<Point2D> regular(double radius, int n);

  bool isCircle() const { return points_.empty(); }
  const std::vector<Point2D>& points() const { return points_; }  // empty for a circle
  double boundingRadius() const { return bounding_radius_; }
  // How far the outline reaches along the base_link direction `angle` (its support distance).
  double reach(double angle) const;
  // The outline placed at `pose` on the table (map frame): a polygon's vertices, or a circle
  // drawn with `segments` vertices (for markers; contacts use the exact shape).
  std::vector<Point2D> placed(const Pose2D& pose, int segments = 48) const;

  // The outline at `pose` against a straight wall: the free side is {p : p . normal <= offset}
  // (normal: unit, pointing into the wall).
  Contact wallContact(const Pose2D& pose, const Point2D& normal, double offset) const;
  // Against each border of the table [0, length] x [0, width] (x = 0, x = length, y = 0, y =
  // width), and the nearest of them.
  std::array<Contact, 4> borderContacts(const Pose2D& pose, double length, double width) const;
  Contact borderContact(const Pose2D& pose, double length, double width) const;
  // The outline at `pose` against a circle.
  Contact circleContact(const Pose2D& pose, const Circle& c) const;
  // Moves a circle overlapping the outline at `pose` out of it until it just touches; true when it moved.
  bool pushOut(const Pose2D& pose, Circle& c) const;

 private:
  Footprint() = default;
  std::vector<Point2D> points_;
  double bounding_radius_ = 0.0;
};

// A footprint standing at a pose: what the opponent and the elements meet.
struct PlacedFootprint {
  const Footprint* shape;
  Pose2D pose;
  Contact circleContact(const Circle& c) const { return shape->circleContact(pose, c); }
  bool pushOut(Circle& c) const { return shape->pushOut(pose, c); }
};

// Polygon `poly` (map) against a circle; a circle whose centre is inside counts as overlapping
// by its distance to the outline plus its radius.
Contact circleContact(const std::vector<Point2D>& poly, const Circle& c);

// The robot's configured outline, or the circle of its radius.
Footprint robotFootprint(const RobotConfig& robot);

bool insidePolygon(const std::vector<Point2D>& poly, double x, double y);

// Moves a circle overlapping the polygon out of it, along the contact normal, until it just
// touches. True when it moved.
bool pushOut(const std::vector<Point2D>& poly, Circle& c);

}  // namespace robot_sim
