#include "hal_nodes/mcl/particle_set.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hal_nodes::mcl {

void ParticleSet::resize(std::size_t n) {
  x.resize(n);
  y.resize(n);
  theta.resize(n);
  w.resize(n, 1.0);
}

double ParticleSet::weightSum() const {
  double s = 0.0;
  for (double v : w) s += v;
  return s;
}

double ParticleSet::getW(size_t i) const {
  return w[i] > 0.0 ? std::log(w[i]) : -std::numeric_limits<double>::infinity();
}

void ParticleSet::setW(size_t i, double log_w) { w[i] = std::exp(log_w); }

double ParticleSet::normalizeWeights(double* out_max_log_w) {
  if (w.empty()) return 0.0;
  double mx = 0.0, mn = std::numeric_limits<double>::infinity();
  for (double v : w) {
    mx = std::max(mx, v);
    mn = std::min(mn, v);
  }
  if (!(mx > 0.0) || !std::isfinite(mx)) {
    // Every particle impossible (the filter handles it before MRPT gets here): keep uniform.
    std::fill(w.begin(), w.end(), 1.0);
    if (out_max_log_w) *out_max_log_w = 0.0;
    return 1.0;
  }
  const double inv = 1.0 / mx;
  for (double& v : w) v *= inv;
  if (out_max_log_w) *out_max_log_w = std::log(mx);
  return mn > 0.0 ? mx / mn : std::numeric_limits<double>::infinity();
}

double ParticleSet::ESS() const {
  double s = 0.0, s2 = 0.0;
  for (double v : w) {
    s += v;
    s2 += v * v;
  }
  if (s2 <= 0.0 || w.empty()) return 0.0;
  return (s * s) / (s2 * static_cast<double>(w.size()));
}

void ParticleSet::performSubstitution(const std::vector<size_t>& indx) {
  const std::size_t m = indx.size();
  if (m == 0) return;
  const std::size_t n = hooks_ ? std::max<std::size_t>(1, hooks_->resampledCount(*this, indx)) : m;
  const double u = hooks_ ? hooks_->uniform() : 0.0;
  nx_.resize(n);
  ny_.resize(n);
  nt_.resize(n);
  // Systematic thinning / replication of MRPT's surviving indices to the new count: for
  // n == m it is exactly indx; otherwise every survivor is kept about n/m times.
  const double step = static_cast<double>(m) / static_cast<double>(n);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t j = std::min(m - 1, static_cast<std::size_t>((static_cast<double>(k) + u) * step));
    const std::size_t src = indx[j];
    nx_[k] = x[src];
    ny_[k] = y[src];
    nt_[k] = theta[src];
  }
  x.swap(nx_);
  y.swap(ny_);
  theta.swap(nt_);
  w.assign(n, 1.0);
  if (hooks_) hooks_->afterResampling(*this);
}

void ParticleSet::prediction_and_update_pfStandardProposal(const mrpt::obs::CActionCollection*,
                                                           const mrpt::obs::CSensoryFrame*,
                                                           const mrpt::bayes::CParticleFilter::TParticleFilterOptions&) {
  if (hooks_) hooks_->predictAndUpdate(*this);
}

}  // namespace hal_nodes::mcl
