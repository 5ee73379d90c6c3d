// Beacon ranges as a checking input. Each distance to a known beacon raises the weight of the
// particles in the circular belt around the beacon and lowers the others:
//   p(r | pose) = (1 - outlier) * N(e; sigma) + outlier / outlier_span  if 0 < e < outlier_span
//                 (1 - outlier) * N(e; sigma) + tiny                    otherwise
// with e = r - |pose - beacon| (the outlier term: a reflected pulse travels a longer path, so
// outliers are long; they must not kill a good particle). sigma is
// the measurement's own standard deviation when it carries one, else ~range_std; with
// range_std_auto the filter learns it from its innovations (the noise of a real receiver is
// not known in advance).
//
// Intersections of two and three belts weigh more, to find the robot faster: while the
// filter is not confident (quality below intersection_below) a particle near the belts of
// the other beacons' recent ranges gets an extra factor (1 + intersection_gain * m), m in
// [0, 1] its membership of those belts (two belts: product of two memberships; three: of all).
// When confident this would double-count old ranges, so it is off.
//
// Recent ranges of at least two beacons also allow trilateration: as a PoseSampler it proposes
// positions at the belt intersections inside the table (heading drawn uniformly).
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "hal_nodes/mcl/checks/table_model.h"
#include "hal_nodes/mcl/input.h"

namespace hal_nodes::mcl {

struct BeaconBeltsConfig {
  std::vector<std::array<double, 2>> beacons;  // [m] positions in the map frame, index = id
  double range_std = 0.015;           // [m] when the measurement has no variance
  bool use_measurement_variance = true;
  bool range_std_auto = false;        // learn sigma from innovations
  double outlier_probability = 0.05;
  double outlier_span = 0.6;          // [m] reflections are at most this much longer
  double reliability = 1.0;
  double intersection_gain = 4.0;
  double intersection_below = 0.5;    // apply the intersection weighting below this quality
  double belt_max_age = 0.25;         // [s] a range older than this no longer forms a belt
  double max_speed = 1.0;             // [m/s] widens an old belt by max_speed * age
};

class BeaconBelts : public CheckingInput, public PoseSampler {
 public:
  BeaconBelts(const BeaconBeltsConfig& cfg, std::shared_ptr<const TableModel> table);

  struct Range {
    double stamp = -1e300;  // [s]
    double range = 0.0;     // [m]
    double sigma = 0.0;     // [m]
  };

  // A new measurement; variance <= 0 (or use_measurement_variance false): use the configured sigma.
  // Returns false (and counts it) for an unknown id or a non-finite / negative range.
  bool addRange(double stamp, int beacon_id, double range, double variance = 0.0);
  const std::vector<Range>& latest() const { return latest_; }
  const BeaconBeltsConfig& config() const { return cfg_; }
  unsigned long rejected() const { return rejected_; }
  double learnedStd() const { return learned_std_; }

  // ---- CheckingInput ----
  bool ready(const StepContext&) const override { return pending_ >= 0; }
  void check(ParticleSet& set, const StepContext& ctx) override;
  bool monitorsLikelihood() const override { return true; }
  bool evidence(double* predictive, double* uninformed) const override;
  bool innovation(double* nis) const override;
  void clear() override { pending_ = -1; }

  // ---- PoseSampler: trilateration from the recent ranges ----
  bool canSample(const StepContext& ctx) const override;
  Pose2D sample(const StepContext& ctx) override;

  // Intersections of the belts of beacons i and j inside the table (0, 1 or 2 points).
  int intersections(int i, int j, double ri, double rj, double out[2][2]) const;

 private:
  double sigmaFor(double variance) const;
  void updateCandidates(const StepContext& ctx) const;

  BeaconBeltsConfig cfg_;
  std::shared_ptr<const TableModel> table_;
  std::vector<Range> latest_;
  int pending_ = -1;        // beacon id of the measurement to apply, -1: none
  double pending_sigma_ = 0.0;
  // evidence of the last applied range: predictive density, density without a pose (1 / the
  // span of the beacon's distances over the table)
  double evidence_pred_ = -1.0, evidence_uninformed_ = 0.0;
  double nis_ = -1.0;  // of the range just applied (-1: none)
  std::vector<double> span_;  // per beacon: farthest table corner [m]
  unsigned long rejected_ = 0;
  // innovation statistics for range_std_auto
  double learned_std_ = 0.0;
  double innov_sq_ = 0.0;
  int innov_n_ = 0;
  // trilateration candidates (cached per step)
  mutable double cand_stamp_ = -1e300;
  mutable std::vector<std::array<double, 3>> cand_;  // x, y, spread
};

}  // namespace hal_nodes::mcl
