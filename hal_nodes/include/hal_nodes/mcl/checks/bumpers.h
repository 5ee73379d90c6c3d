// Bumpers as a checking input: a closed bumper means a border (or fixed obstacle) touches the
// robot at that bumper's contact point. For each closed bumper, with d the distance from its
// contact point (base_link, composed with the particle) to the nearest table edge:
//   p = (1 - other) * exp(-0.5 * (max(0, d - tolerance) / std)^2) + other
// (other: it may be pushing the opponent or a game element instead). An open bumper says
// nothing (the table model already forbids being through a border).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "hal_nodes/mcl/checks/table_model.h"
#include "hal_nodes/mcl/input.h"

namespace hal_nodes::mcl {

struct BumperConfig {
  std::string name;
  double x = 0.0, y = 0.0;  // contact point in base_link [m]
};

struct BumpersOptions {
  double tolerance = 0.01;          // [m]
  double std = 0.02;                // [m]
  double other_probability = 0.3;
  double reliability = 0.5;
  double min_interval = 0.2;        // [s] between applications while a bumper stays closed
};

class Bumpers : public CheckingInput {
 public:
  Bumpers(const std::vector<BumperConfig>& bumpers, const BumpersOptions& opts, std::shared_ptr<const TableModel> table);
  // The names closed now (unknown names are counted and ignored).
  void setClosed(double stamp, const std::vector<std::string>& closed);
  unsigned long unknown() const { return unknown_; }
  bool ready(const StepContext& ctx) const override;
  void check(ParticleSet& set, const StepContext& ctx) override;
  void clear() override { closed_.clear(); }
  double likelihood(const Pose2D& pose) const;  // of the current closed set (tests)

 private:
  std::vector<BumperConfig> bumpers_;
  BumpersOptions opts_;
  std::shared_ptr<const TableModel> table_;
  std::vector<std::size_t> closed_;
  double last_applied_ = -1e300;
  bool changed_ = false;
  unsigned long unknown_ = 0;
};

}  // namespace hal_nodes::mcl
