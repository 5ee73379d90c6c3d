// The table model: the robot's centre can only be on the table,
// at least `margin` (the robot's radius) from the borders and outside fixed obstacles (each
// inflated by the margin). As a checking input it makes impossible particles weigh zero at
// every step; the filter also projects its final estimate into free space with it, samples
// uniform free poses from it (global localization), and the rangers and bumpers measure
// against its borders.
#pragma once

#include <robot_core/table_geometry.h>

#include <vector>

#include "hal_nodes/mcl/input.h"

namespace hal_nodes::mcl {

using robot_core::Rect;

class TableModel : public CheckingInput {
 public:
  // length along x, width along y [m]; margin: the robot's radius [m].
  TableModel(double length, double width, double margin = 0.0, std::vector<Rect> obstacles = {});

  double length() const { return geometry_.length(); }
  double width() const { return geometry_.width(); }
  double margin() const { return margin_; }
  const std::vector<Rect>& obstacles() const { return geometry_.blocks(); }
  // The raw table (no margin): what the rangers and bumpers measure against.
  const robot_core::TableGeometry& geometry() const { return geometry_; }

  // Whether the robot's centre may be at (x, y).
  bool isFree(double x, double y) const;
  // The nearest free position (the point itself when free).
  void project(double& x, double& y) const;
  // A uniform free pose, all headings (rejection sampling).
  Pose2D sampleFree(Rng& rng) const;
  // ---- CheckingInput: applied at every step ----
  bool ready(const StepContext&) const override { return true; }
  void check(ParticleSet& set, const StepContext& ctx) override;

 private:
  robot_core::TableGeometry geometry_;
  double margin_;
  std::vector<Rect> inflated_;  // the blocks grown by the margin, for isFree
};

}  // namespace hal_nodes::mcl
