// Avoidance: is the opponent on the route ahead, and where to go around it.
//
// The route is the polyline the robot is about to drive (from its position: to the goal, or
// along the sampled curve). An obstacle point (a ranger echo or the tracked opponent, in the
// map) blocks it when our footprint, moving along the route, would come within `clearance()`
// of it in the first `detection_distance` metres (Hit::along: where that starts).
// Echoes within `border_margin` of the table edge are the border, not the opponent; so is a
// ranger echo whose range matches the nearest border anywhere in the sensor's cone (a wide
// ultrasonic beam sees a border off its axis, and the echo placed on the axis would land
// inside the table, on the route: borderExplains()). Points level with or behind the robot
// (on the route's first leg) are not in its way.
// The driver then either brakes to a stop within `braking_distance` and waits (mode STOP), or
// inserts a detour of two waypoints beside the obstacle on the side that stays on the table
// (mode DETOUR), falling back to a stop when neither side fits. Pure geometry, tested alone.
#pragma once

#include <string>
#include <vector>

#include "hal_nodes/driver/geometry.h"

namespace hal_nodes {
namespace driver {

struct AvoidanceConfig {
  enum class Mode { OFF, STOP, DETOUR };
  Mode mode = Mode::STOP;
  double robot_radius = 0.18;        // [m] our footprint's circumscribed radius
  double opponent_radius = 0.2;      // [m] assumed size around an opponent point
  double margin = 0.05;              // [m] extra room kept around the opponent
  double detection_distance = 0.7;   // [m] how far ahead along the route to look
  double braking_distance = 0.2;     // [m] the robot stops within this after a detection
  double border_margin = 0.06;       // [m] echoes this close to the table edge are ignored
  double border_echo_tolerance = 0.1; // [m] a ranger echo this close to the border range in its cone is the border
  double table_length = 3.0;         // [m] x extent of the table (map frame)
  double table_width = 2.1;          // [m] y extent
  double blocked_timeout = 3.0;      // [s] stopped this long for an obstacle: abort the goal
  int max_detours = 3;               // per goal; more: stop instead

  double clearance() const { return robot_radius + opponent_radius + margin; }
  std::string invalidReason() const;  // empty when usable
  static bool parseMode(const std::string& s, Mode* mode);
};

class Avoidance {
 public:
  struct Hit {
    bool blocked = false;
    double along = 0.0;  // distance along the route at which the footprint would touch [m]
    Point2D obstacle;
    Point2D direction;   // unit route direction there
  };

  explicit Avoidance(const AvoidanceConfig& config) : config_(config) {}

  // Whether an echo at `p` may be the opponent (inside the table, away from its edges).
  bool plausibleObstacle(const Point2D& p) const;
  // The shortest distance from `sensor` (in the map) to the table border within the cone
  // heading +- field_of_view / 2 (what a ranger there reads on an empty table).
  double borderRange(const Pose2D& sensor, double field_of_view) const;
  // Whether a ranger reading `range` at `sensor` is the border seen somewhere in its cone,
  // not something nearer (within border_echo_tolerance of borderRange, or beyond it).
  bool borderExplains(const Pose2D& sensor, double field_of_view, double range) const;
  // The nearest obstacle blocking `route` (route[0] is the robot) within detection_distance.
  Hit check(const std::vector<Point2D>& route, const std::vector<Point2D>& obstacles) const;
  // Two waypoints beside the obstacle, or false when no side fits on the table.
  bool detour(const Hit& hit, const std::vector<Point2D>& obstacles, std::vector<Point2D>* waypoints) const;
  const AvoidanceConfig& config() const { return config_; }

 private:
  bool fits(const Point2D& p) const;  // a robot centred at p stays on the table
  AvoidanceConfig config_;
};

}  // namespace driver
}  // namespace hal_nodes
