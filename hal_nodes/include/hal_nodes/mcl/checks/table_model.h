// The table model (the original RangeManager): the robot's centre can only be on the table,
// at least `margin` (the robot's radius) from the borders and outside fixed obstacles (each
// inflated by the margin). As a checking input it makes impossible particles weigh zero at
// every step; the filter also projects its final estimate into free space with it, samples
// uniform free poses from it (global localization), and the rangers and bumpers measure
// against its borders.
#pragma once

#include <vector>

#include "hal_nodes/mcl/input.h"

namespace hal_nodes::mcl {

struct Rect {
  double x0, y0, x1, y1;  // axis-aligned, x0 < x1, y0 < y1 [m]
};

class TableModel : public CheckingInput {
 public:
  // length along x, width along y [m]; margin: the robot's radius [m].
  TableModel(double length, double width, double margin = 0.0, std::vector<Rect> obstacles = {});

  double length() const { return length_; }
  double width() const { return width_; }
  double margin() const { return margin_; }
  const std::vector<Rect>& obstacles() const { return obstacles_; }

  // Whether the robot's centre may be at (x, y).
  bool isFree(double x, double y) const;
  // The nearest free position (the point itself when free).
  void project(double& x, double& y) const;
  // A uniform free pose, all headings (rejection sampling).
  Pose2 sampleFree(Rng& rng) const;
  // Distance from (x, y) along direction `angle` to the first border or obstacle (raw
  // geometry, no margin); 0 if (x, y) is already outside the table or inside an obstacle.
  double rayCast(double x, double y, double angle, double max_range) const;
  // Distance from (x, y) to the nearest border or obstacle point inside the cone of full width
  // `beam_width` around `angle`: the first echo of a sonar (its cone, not its centre line);
  // beam_width 0 is rayCast. Exact: on each edge the nearest point of the cone lies at the
  // foot of the perpendicular, at a corner, or where a cone edge crosses it.
  double coneRange(double x, double y, double angle, double beam_width, double max_range) const;
  // Distance from (x, y) to the nearest border or obstacle edge (raw geometry, no margin);
  // 0 when outside the table or inside an obstacle.
  double distanceToEdge(double x, double y) const;

  // ---- CheckingInput: applied at every step ----
  bool ready(const StepContext&) const override { return true; }
  void check(ParticleSet& set, const StepContext& ctx) override;

 private:
  double length_, width_, margin_;
  std::vector<Rect> obstacles_;  // raw
  std::vector<Rect> inflated_;   // by the margin, for isFree
};

}  // namespace hal_nodes::mcl
