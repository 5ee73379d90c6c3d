// The particle cluster an estimate comes from. A multimodal cloud (two places the beacons
// cannot tell apart, a kidnap half recovered) has a meaningless overall mean and a covariance
// that describes the gap between its modes, not the uncertainty of any one of them: amcl and
// mrpt_localization report that whole-set covariance. Here the particles are binned on a grid
// (x, y, heading, the heading wrapping round), occupied cells touching each other (26
// neighbours) form one cluster, and the estimate is the heaviest cluster's weighted mean and
// covariance, as amcl picks its pose from its heaviest kd-tree cluster.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "hal_nodes/mcl/particle_set.h"
#include "hal_nodes/mcl/pose.h"

namespace hal_nodes::mcl {

struct ClusterStats {
  Pose2D mean;
  std::array<double, 9> cov{};  // x, y, theta (row-major), heading relative to the mean
  double weight = 0.0;          // share of the set's weight, in [0, 1]
  std::size_t particles = 0;
};

// The weighted circular mean heading of the particles labelled `keep` (all when labels is null).
double circularMean(const ParticleSet& set, const std::vector<int>* labels = nullptr, int keep = 0);
// The weighted headings measured from `from`: their circular mean (relative to `from`) and mean
// resultant length R (1: all alike, 0: spread evenly; the wrapped normal's variance is -2 ln R).
struct HeadingSpread {
  double mean = 0.0;
  double resultant = 0.0;
  double weight = 0.0;  // their weights' sum
};
HeadingSpread headingSpread(const ParticleSet& set, double from = 0.0, const std::vector<int>* labels = nullptr, int keep = 0);
// Weighted mean and covariance of the particles labelled `keep` (all when labels is null), the
// heading taken relative to `ref_theta` (a cluster across +-pi is not torn apart when ref_theta
// is near its mean: circularMean(), or a previous estimate, which spares the trigonometry).
// weight 0 when their weights sum to 0.
ClusterStats weightedStats(const ParticleSet& set, double ref_theta, const std::vector<int>* labels = nullptr,
                           int keep = 0);

class Clustering {
 public:
  Clustering(double bin_xy, double bin_theta);
  // The heaviest cluster of the set. Reuses its buffers: no allocation once warmed up.
  ClusterStats heaviest(const ParticleSet& set);
  // How many clusters the last call found.
  std::size_t count() const { return clusters_; }

 private:
  int find(int cell);
  std::int64_t key(long ix, long iy, long it) const;

  double bin_xy_, bin_theta_;
  long theta_cells_;
  std::unordered_map<std::int64_t, int> cells_;  // cell key -> cell index
  std::vector<int> parent_;                      // union-find over cells
  std::vector<long> cx_, cy_, ct_;               // each cell's coordinates
  std::vector<int> particle_cell_, labels_;
  std::vector<double> cluster_weight_;
  std::size_t clusters_ = 0;
};

}  // namespace hal_nodes::mcl
