// Range finders (SRF02 sonars, infrared) as a checking input, measured against the table
// borders and fixed obstacles of the table model. For each ranger with a new reading r:
//   expected e = the nearest edge inside the ranger's cone (robot_core::TableGeometry::coneRange) from the
//   ranger's pose (mounting pose on the robot composed with the particle), capped at max_range.
//   The cone is the configured beam_width, or the reading's own (sensor_msgs/Range
//   field_of_view) when beam_width < 0. A sonar answers with its nearest echo anywhere in its
//   cone: a side sonar at 45 deg to a border reads up to a quarter shorter than its centre line, and
//   measuring it as the centre line pulled the heading 2-3 deg off while driving;
//   reading at (or beyond) max_range: p = e >= max_range ? 1 - short : miss_probability;
//   reading at (or under) min_range: the part reads its minimum for anything nearer (an SRF02
//   says 16 cm of a border 8 cm away), so it means "this near or nearer", not "exactly here":
//   p = (1 - short) * P(e <= min_range + noise) + short * min_range / max_range;
//   otherwise p = (1 - short) * N(r - e; std) + short / max_range
// (short: something not in the map in front of it, such as the opponent or a game element).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "hal_nodes/mcl/checks/table_model.h"
#include "hal_nodes/mcl/input.h"

namespace hal_nodes::mcl {

struct RangerConfig {
  std::string name;
  double x = 0.0, y = 0.0, yaw = 0.0;  // mounting pose in base_link [m, rad]
  double min_range = 0.03, max_range = 2.0;  // [m] the part's own limits (what it reads for nearer / nothing)
  double beam_width = -1.0;                  // [rad] full cone; < 0: each reading's field_of_view
  double std = 0.02;                         // [m]
  double short_probability = 0.2;
  double miss_probability = 0.2;
  double min_interval = 0.05;                // [s] between applied readings of one ranger
};

class Rangers : public CheckingInput {
 public:
  Rangers(const std::vector<RangerConfig>& rangers, double reliability, std::shared_ptr<const TableModel> table);
  std::size_t index(const std::string& name) const;  // throws std::out_of_range
  // field_of_view: the reading's cone [rad] (used when the ranger's beam_width < 0).
  // range -inf / +inf (REP 117): nearer than min_range / nothing within max_range.
  bool addRange(std::size_t ranger, double stamp, double range, double field_of_view = 0.0);  // false: rejected (NaN)
  bool ready(const StepContext&) const override;
  void check(ParticleSet& set, const StepContext& ctx) override;
  void clear() override;
  // The likelihood of one reading from one pose (exposed for tests).
  double likelihood(std::size_t ranger, const Pose2D& pose, double range, double beam_width = 0.0) const;

 private:
  struct State {
    RangerConfig cfg;
    bool pending = false;
    double range = 0.0;
    double beam_width = 0.0;  // of the pending reading
    double last_applied = -1e300;
  };
  std::vector<State> rangers_;
  std::shared_ptr<const TableModel> table_;
};

}  // namespace hal_nodes::mcl
