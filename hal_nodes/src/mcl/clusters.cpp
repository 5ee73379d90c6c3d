#include "hal_nodes/mcl/clusters.h"

#include <algorithm>
#include <cmath>

namespace hal_nodes::mcl {

HeadingSpread headingSpread(const ParticleSet& set, double from, const std::vector<int>* labels, int keep) {
  double sw = 0.0, sc = 0.0, ss = 0.0;
  for (std::size_t i = 0; i < set.size(); ++i) {
    if (labels != nullptr && (*labels)[i] != keep) continue;
    sw += set.w[i];
    sc += set.w[i] * std::cos(set.theta[i] - from);
    ss += set.w[i] * std::sin(set.theta[i] - from);
  }
  HeadingSpread out;
  out.mean = std::atan2(ss, sc);
  out.resultant = sw > 0.0 ? std::hypot(sc, ss) / sw : 0.0;
  out.weight = sw;
  return out;
}

double circularMean(const ParticleSet& set, const std::vector<int>* labels, int keep) {
  return headingSpread(set, 0.0, labels, keep).mean;
}

ClusterStats weightedStats(const ParticleSet& set, double ref, const std::vector<int>* labels, int keep) {
  ClusterStats s;
  double sw = 0, sx = 0, sy = 0, st = 0, sxx = 0, syy = 0, sxy = 0, stt = 0, sxt = 0, syt = 0;
  for (std::size_t i = 0; i < set.size(); ++i) {
    if (labels != nullptr && (*labels)[i] != keep) continue;
    const double wi = set.w[i], x = set.x[i], y = set.y[i], dt = wrapAngle(set.theta[i] - ref);
    sw += wi;
    sx += wi * x;
    sy += wi * y;
    st += wi * dt;
    sxx += wi * x * x;
    syy += wi * y * y;
    sxy += wi * x * y;
    stt += wi * dt * dt;
    sxt += wi * x * dt;
    syt += wi * y * dt;
    ++s.particles;
  }
  if (!(sw > 0.0)) return s;
  const double mx = sx / sw, my = sy / sw, mt = st / sw;
  s.mean = {mx, my, wrapAngle(ref + mt)};
  s.cov[0] = std::max(0.0, sxx / sw - mx * mx);
  s.cov[4] = std::max(0.0, syy / sw - my * my);
  s.cov[8] = std::max(0.0, stt / sw - mt * mt);
  s.cov[1] = s.cov[3] = sxy / sw - mx * my;
  s.cov[2] = s.cov[6] = sxt / sw - mx * mt;
  s.cov[5] = s.cov[7] = syt / sw - my * mt;
  s.weight = 1.0;
  return s;
}

Clustering::Clustering(double bin_xy, double bin_theta)
    : bin_xy_(bin_xy), bin_theta_(bin_theta), theta_cells_(std::max(1L, static_cast<long>(std::floor(2.0 * M_PI / bin_theta)))) {}

std::int64_t Clustering::key(long ix, long iy, long it) const {
  // x and y within +-2^20 cells (kilometres at any sane bin), the heading below 2^10 cells.
  const long w = ((it % theta_cells_) + theta_cells_) % theta_cells_;
  return (static_cast<std::int64_t>(ix + (1L << 20)) << 32) | (static_cast<std::int64_t>(iy + (1L << 20)) << 10) | w;
}

int Clustering::find(int c) {
  while (parent_[c] != c) {
    parent_[c] = parent_[parent_[c]];
    c = parent_[c];
  }
  return c;
}

ClusterStats Clustering::heaviest(const ParticleSet& set) {
  const std::size_t n = set.size();
  cells_.clear();
  parent_.clear();
  cx_.clear();
  cy_.clear();
  ct_.clear();
  particle_cell_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const long ix = static_cast<long>(std::floor(set.x[i] / bin_xy_));
    const long iy = static_cast<long>(std::floor(set.y[i] / bin_xy_));
    const long it = static_cast<long>(std::floor((wrapAngle(set.theta[i]) + M_PI) / bin_theta_)) % theta_cells_;
    const auto ins = cells_.emplace(key(ix, iy, it), static_cast<int>(parent_.size()));
    if (ins.second) {
      parent_.push_back(static_cast<int>(parent_.size()));
      cx_.push_back(ix);
      cy_.push_back(iy);
      ct_.push_back(it);
    }
    particle_cell_[i] = ins.first->second;
  }
  // Every occupied cell joins each occupied neighbour (the heading wraps round).
  for (std::size_t c = 0; c < parent_.size(); ++c) {
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dt = -1; dt <= 1; ++dt) {
          if (dx == 0 && dy == 0 && dt == 0) continue;
          const auto it = cells_.find(key(cx_[c] + dx, cy_[c] + dy, ct_[c] + dt));
          if (it == cells_.end()) continue;
          const int a = find(static_cast<int>(c)), b = find(it->second);
          if (a != b) parent_[std::max(a, b)] = std::min(a, b);
        }
  }
  labels_.resize(n);
  cluster_weight_.assign(parent_.size(), 0.0);
  double total = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    labels_[i] = find(particle_cell_[i]);
    cluster_weight_[labels_[i]] += set.w[i];
    total += set.w[i];
  }
  clusters_ = 0;
  int best = 0;
  for (std::size_t c = 0; c < cluster_weight_.size(); ++c) {
    if (static_cast<int>(c) != find(static_cast<int>(c))) continue;
    ++clusters_;
    if (cluster_weight_[c] > cluster_weight_[best]) best = static_cast<int>(c);
  }
  ClusterStats s = weightedStats(set, circularMean(set, &labels_, best), &labels_, best);
  s.weight = total > 0.0 ? cluster_weight_[best] / total : 0.0;
  return s;
}

}  // namespace hal_nodes::mcl
