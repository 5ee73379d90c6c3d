#include "hal_nodes/mcl/checks/beacon_belts.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hal_nodes::mcl {

namespace {
constexpr double kInvSqrt2Pi = 0.3989422804014327;
constexpr double kLearnAlpha = 0.01;  // innovation average over ~100 ranges
}  // namespace

BeaconBelts::BeaconBelts(const BeaconBeltsConfig& cfg, std::shared_ptr<const TableModel> table)
    : CheckingInput("beacons", cfg.reliability), cfg_(cfg), table_(std::move(table)) {
  if (cfg_.beacons.empty()) throw std::invalid_argument("beacons: the beacon list is empty");
  if (!(cfg_.range_std > 0.0)) throw std::invalid_argument("beacons: range_std must be > 0");
  if (!(cfg_.outlier_probability >= 0.0 && cfg_.outlier_probability < 1.0))
    throw std::invalid_argument("beacons: outlier_probability must be in [0, 1)");
  if (!(cfg_.outlier_span > 0.0)) throw std::invalid_argument("beacons: outlier_span must be > 0");
  if (!(cfg_.reliability >= 0.0 && cfg_.reliability <= 1.0))
    throw std::invalid_argument("beacons: reliability must be in [0, 1]");
  if (!table_) throw std::invalid_argument("beacons: a table model is needed");
  latest_.resize(cfg_.beacons.size());
  for (const auto& b : cfg_.beacons) {
    double far = 0.0;
    for (double cx : {0.0, table_->length()})
      for (double cy : {0.0, table_->width()}) far = std::max(far, std::hypot(cx - b[0], cy - b[1]));
    span_.push_back(std::max(far, 0.1));
  }
  learned_std_ = cfg_.range_std;
  innov_sq_ = cfg_.range_std * cfg_.range_std;
}

double BeaconBelts::sigmaFor(double variance) const {
  if (cfg_.use_measurement_variance && variance > 0.0 && std::isfinite(variance)) return std::sqrt(variance);
  return cfg_.range_std_auto ? learned_std_ : cfg_.range_std;
}

bool BeaconBelts::addRange(double stamp, int id, double range, double variance) {
  if (id < 0 || id >= static_cast<int>(latest_.size()) || !std::isfinite(range) || range < 0.0 || !std::isfinite(stamp)) {
    ++rejected_;
    return false;
  }
  Range& r = latest_[id];
  r.stamp = stamp;
  r.range = range;
  r.sigma = sigmaFor(variance);
  pending_ = id;
  pending_sigma_ = r.sigma;
  return true;
}

void BeaconBelts::check(ParticleSet& set, const StepContext& ctx) {
  if (pending_ < 0) return;
  const int id = pending_;
  pending_ = -1;
  const double bx = cfg_.beacons[id][0], by = cfg_.beacons[id][1];
  const double r = latest_[id].range, sigma = pending_sigma_;
  const double a = (1.0 - cfg_.outlier_probability) * kInvSqrt2Pi / sigma;
  const double c = -0.5 / (sigma * sigma);
  const double span = cfg_.outlier_span;
  const double u = cfg_.outlier_probability / span;
  const double floor = 1e-3 * u;  // never exactly zero: a short reading must not kill a particle

  // Belts of the other beacons' recent ranges, for the intersection weighting.
  struct Other {
    double x, y, r, c;
  };
  Other others[8];
  int n_others = 0;
  if (cfg_.intersection_gain > 0.0 && ctx.quality < cfg_.intersection_below) {
    for (int j = 0; j < static_cast<int>(latest_.size()) && n_others < 8; ++j) {
      if (j == id) continue;
      const double age = ctx.now - latest_[j].stamp;
      if (!(age >= 0.0 && age <= cfg_.belt_max_age)) continue;
      const double s2 = latest_[j].sigma * latest_[j].sigma + (cfg_.max_speed * age) * (cfg_.max_speed * age);
      others[n_others++] = {cfg_.beacons[j][0], cfg_.beacons[j][1], latest_[j].range, -0.5 / s2};
    }
  }

  const std::size_t n = set.size();
  const double* px = set.x.data();
  const double* py = set.y.data();
  double* w = set.w.data();
  const double rel = reliability();
  double sw = 0.0, swd = 0.0, swd2 = 0.0;  // predicted range statistics (innovation learning)
  double swl = 0.0;                        // prior-weighted base likelihood (evidence)
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = px[i] - bx, dy = py[i] - by;
    const double d = std::sqrt(dx * dx + dy * dy);
    const double e = r - d;
    // Reflections only make a range longer: the outlier term lives on the long side.
    double lik = a * std::exp(c * e * e) + (e > 0.0 && e < span ? u : floor);
    swl += w[i] * lik;  // before the intersection boost: evidence must not depend on the quality
    if (n_others > 0) {
      double sum = 0.0, prod = 1.0;
      for (int k = 0; k < n_others; ++k) {
        const double ox = px[i] - others[k].x, oy = py[i] - others[k].y;
        const double eo = others[k].r - std::sqrt(ox * ox + oy * oy);
        const double m = std::exp(others[k].c * eo * eo);
        sum += m;
        prod *= m;
      }
      lik *= 1.0 + cfg_.intersection_gain * (sum + (n_others >= 2 ? prod : 0.0));
    }
    const double wi = w[i];
    sw += wi;
    swd += wi * d;
    swd2 += wi * d * d;
    w[i] = wi * (rel == 1.0 ? lik : std::pow(lik, rel));
  }
  evidence_pred_ = sw > 0.0 ? swl / sw : -1.0;
  evidence_uninformed_ = 1.0 / span_[id];
  nis_ = -1.0;
  if (sw > 0.0) {
    const double mean = swd / sw, var_pred = std::max(0.0, swd2 / sw - mean * mean);
    nis_ = (r - mean) * (r - mean) / (sigma * sigma + var_pred);
  }

  // Learn the range noise from innovations while tracking well: innovation^2 = noise^2 +
  // spread of the predicted range; gross outliers (beyond 4 sigma) do not count.
  if (cfg_.range_std_auto && sw > 0.0 && ctx.quality > 0.5) {
    const double mean = swd / sw;
    const double var_pred = std::max(0.0, swd2 / sw - mean * mean);
    const double innov = r - mean;
    const double gate = 4.0 * std::sqrt(learned_std_ * learned_std_ + var_pred);
    if (std::fabs(innov) < gate) {
      innov_sq_ += kLearnAlpha * (innov * innov - var_pred - innov_sq_);
      ++innov_n_;
      // Learned sigma kept within a factor 3 of the configured one.
      learned_std_ = std::clamp(std::sqrt(std::max(innov_sq_, 0.0)), cfg_.range_std / 3.0, cfg_.range_std * 3.0);
    }
  }
}

bool BeaconBelts::evidence(double* predictive, double* uninformed) const {
  if (evidence_pred_ < 0.0) return false;
  // Even when tracking, a range is sometimes garbage whatever the pose (the model's floor for
  // short ranges is deliberately tiny): one such range must not say "lost" on its own.
  const double o = cfg_.outlier_probability;
  *predictive = (1.0 - o) * evidence_pred_ + o * evidence_uninformed_;
  *uninformed = evidence_uninformed_;
  return true;
}

bool BeaconBelts::innovation(double* nis) const {
  if (nis_ < 0.0) return false;
  *nis = nis_;
  return true;
}

int BeaconBelts::intersections(int i, int j, double ri, double rj, double out[2][2]) const {
  const double x0 = cfg_.beacons[i][0], y0 = cfg_.beacons[i][1];
  const double x1 = cfg_.beacons[j][0], y1 = cfg_.beacons[j][1];
  const double dx = x1 - x0, dy = y1 - y0, d = std::hypot(dx, dy);
  if (d < 1e-9) return 0;
  const double a = (ri * ri - rj * rj + d * d) / (2.0 * d);
  double h2 = ri * ri - a * a;
  if (h2 < 0.0) {
    if (h2 < -0.01 * d * d) return 0;  // belts too far apart: inconsistent ranges
    h2 = 0.0;                          // nearly tangent: take the touching point
  }
  const double h = std::sqrt(h2);
  const double mx = x0 + a * dx / d, my = y0 + a * dy / d;
  int n = 0;
  const double cand[2][2] = {{mx - h * dy / d, my + h * dx / d}, {mx + h * dy / d, my - h * dx / d}};
  for (int k = 0; k < (h > 0.0 ? 2 : 1); ++k) {
    if (!table_->isFree(cand[k][0], cand[k][1])) continue;
    out[n][0] = cand[k][0];
    out[n][1] = cand[k][1];
    ++n;
  }
  return n;
}

void BeaconBelts::updateCandidates(const StepContext& ctx) const {
  if (cand_stamp_ == ctx.now) return;
  cand_stamp_ = ctx.now;
  cand_.clear();
  struct Fresh {
    int id;
    double r, s;
  };
  std::vector<Fresh> fresh;
  for (int j = 0; j < static_cast<int>(latest_.size()); ++j) {
    const double age = ctx.now - latest_[j].stamp;
    if (age >= 0.0 && age <= cfg_.belt_max_age)
      fresh.push_back({j, latest_[j].range, std::hypot(latest_[j].sigma, cfg_.max_speed * age)});
  }
  if (fresh.size() < 2) return;
  for (std::size_t a = 0; a < fresh.size(); ++a) {
    for (std::size_t b = a + 1; b < fresh.size(); ++b) {
      double pts[2][2];
      const int n = intersections(fresh[a].id, fresh[b].id, fresh[a].r, fresh[b].r, pts);
      for (int k = 0; k < n; ++k) {
        // Refine on every fresh range (Gauss-Newton), then test consistency with all of them.
        double x = pts[k][0], y = pts[k][1];
        for (int it = 0; it < 3; ++it) {
          double h00 = 1e-9, h01 = 0, h11 = 1e-9, g0 = 0, g1 = 0;
          for (const auto& f : fresh) {
            const double dx = x - cfg_.beacons[f.id][0], dy = y - cfg_.beacons[f.id][1];
            const double d = std::max(1e-6, std::hypot(dx, dy));
            const double jx = dx / d, jy = dy / d, e = f.r - d, wgt = 1.0 / (f.s * f.s);
            h00 += wgt * jx * jx;
            h01 += wgt * jx * jy;
            h11 += wgt * jy * jy;
            g0 += wgt * jx * e;
            g1 += wgt * jy * e;
          }
          const double det = h00 * h11 - h01 * h01;
          if (std::fabs(det) < 1e-12) break;
          x += (h11 * g0 - h01 * g1) / det;
          y += (-h01 * g0 + h00 * g1) / det;
        }
        if (!table_->isFree(x, y)) continue;
        double chi2 = 0.0, smax = 0.0;
        for (const auto& f : fresh) {
          const double e = f.r - std::hypot(x - cfg_.beacons[f.id][0], y - cfg_.beacons[f.id][1]);
          chi2 += e * e / (f.s * f.s);
          smax = std::max(smax, f.s);
        }
        if (chi2 > 9.0 * static_cast<double>(fresh.size())) continue;
        bool dup = false;
        for (const auto& c : cand_) dup |= std::hypot(c[0] - x, c[1] - y) < smax;
        if (!dup) cand_.push_back({x, y, smax});
      }
    }
  }
}

bool BeaconBelts::canSample(const StepContext& ctx) const {
  updateCandidates(ctx);
  return !cand_.empty();
}

Pose2D BeaconBelts::sample(const StepContext& ctx) {
  updateCandidates(ctx);
  Rng& rng = *ctx.rng;
  if (cand_.empty()) return table_->sampleFree(rng);
  for (int tries = 0; tries < 20; ++tries) {
    const auto& c = cand_[static_cast<std::size_t>(rng.uniform() * cand_.size()) % cand_.size()];
    const double x = c[0] + c[2] * rng.gaussian(), y = c[1] + c[2] * rng.gaussian();
    if (table_->isFree(x, y)) return {x, y, rng.uniform(-M_PI, M_PI)};
  }
  return {cand_[0][0], cand_[0][1], rng.uniform(-M_PI, M_PI)};
}

}  // namespace hal_nodes::mcl
