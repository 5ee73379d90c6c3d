// KLD-sampling bound (Fox 2003): the number of particles such that, with probability 1 - delta
// (z its upper standard normal quantile), the KL divergence between the particle
// approximation and the true posterior stays below epsilon, given k occupied histogram bins.
// The count shrinks when the cloud is tight and grows when it spreads. Bins are counted
// with a fixed-size open-addressing table (no allocation per step).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hal_nodes::mcl {

struct KldParams {
  double epsilon = 0.02;
  double z = 2.33;           // delta = 0.01
  double bin_xy = 0.02;      // [m]
  double bin_theta = 0.05;   // [rad]
};

std::size_t kldBound(std::size_t occupied_bins, const KldParams& p);

class BinCounter {
 public:
  explicit BinCounter(std::size_t max_items = 0) { reserve(max_items); }
  void reserve(std::size_t max_items);
  void clear();
  // Adds the bin of a pose; returns the number of distinct bins so far.
  std::size_t add(double x, double y, double theta, const KldParams& p);
  std::size_t count() const { return count_; }

 private:
  std::vector<uint64_t> table_;
  std::size_t count_ = 0;
  uint64_t mask_ = 0;
};

}  // namespace hal_nodes::mcl
