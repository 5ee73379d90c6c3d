#include "hal_nodes/mcl/filter.h"

#include <mrpt/random/RandomGenerators.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hal_nodes::mcl {

using mrpt::bayes::CParticleFilter;

bool parseResampling(const std::string& name, CParticleFilter::TParticleResamplingAlgorithm* out) {
  if (name == "multinomial") *out = CParticleFilter::prMultinomial;
  else if (name == "residual") *out = CParticleFilter::prResidual;
  else if (name == "stratified") *out = CParticleFilter::prStratified;
  else if (name == "systematic") *out = CParticleFilter::prSystematic;
  else return false;
  return true;
}

Filter::Filter(const FilterConfig& cfg, std::shared_ptr<TableModel> table)
    : cfg_(cfg), table_(std::move(table)), rng_(cfg.seed), clustering_(cfg.cluster_bin_xy, cfg.cluster_bin_theta) {
  if (!table_) throw std::invalid_argument("filter: a table model is needed");
  if (cfg_.max_particles < 1) throw std::invalid_argument("max_particles must be >= 1");
  if (cfg_.min_particles < 1 || cfg_.min_particles > cfg_.max_particles)
    throw std::invalid_argument("min_particles must be in [1, max_particles]");
  if (!(cfg_.cluster_bin_xy > 0.0 && cfg_.cluster_bin_theta > 0.0)) throw std::invalid_argument("cluster bins must be > 0");
  if (!(cfg_.ess_threshold >= 0.0 && cfg_.ess_threshold <= 1.0)) throw std::invalid_argument("ess_threshold must be in [0, 1]");
  if (!(cfg_.alpha_slow > 0.0 && cfg_.alpha_slow < cfg_.alpha_fast && cfg_.alpha_fast <= 1.0))
    throw std::invalid_argument("need 0 < alpha_slow < alpha_fast <= 1");
  if (!(cfg_.track_hazard > 0.0 && cfg_.track_hazard < 0.5)) throw std::invalid_argument("track_hazard must be in (0, 0.5)");
  if (!(cfg_.reset_fraction > 0.0 && cfg_.reset_fraction <= 1.0)) throw std::invalid_argument("reset_fraction must be in (0, 1]");
  if (!(cfg_.kld.epsilon > 0.0 && cfg_.kld.bin_xy > 0.0 && cfg_.kld.bin_theta > 0.0))
    throw std::invalid_argument("kld epsilon and bin sizes must be > 0");
  set_.setHooks(this);
  // MRPT drives the step: standard proposal (our prediction_and_update), the selected
  // resampling scheme when ESS < BETA. Its own adaptive sample size requires multinomial
  // resampling and its own proposal, so the KLD count is applied in performSubstitution instead.
  pf_.m_options.PF_algorithm = CParticleFilter::pfStandardProposal;
  pf_.m_options.resamplingMethod = cfg_.resampling;
  pf_.m_options.adaptiveSampleSize = false;
  pf_.m_options.BETA = cfg_.ess_threshold;
  pf_.m_options.sampleSize = static_cast<unsigned int>(cfg_.max_particles);
  pf_.setMinLoggingLevel(mrpt::system::LVL_ERROR);
  bins_.reserve(cfg_.max_particles);
  ctx_.rng = &rng_;
  globalLocalization();
}

void Filter::addAdvancing(std::shared_ptr<AdvancingInput> input) { advancing_.push_back(std::move(input)); }
void Filter::addChecking(std::shared_ptr<CheckingInput> input) { checking_.push_back(std::move(input)); }
void Filter::addSampler(std::shared_ptr<PoseSampler> sampler) { samplers_.push_back(std::move(sampler)); }

void Filter::setPose(const Pose2D& pose, double std_xy, double std_theta) {
  set_.resize(cfg_.max_particles);
  for (std::size_t i = 0; i < set_.size(); ++i) {
    double x = pose.x + std_xy * rng_.gaussian(), y = pose.y + std_xy * rng_.gaussian();
    table_->project(x, y);
    set_.x[i] = x;
    set_.y[i] = y;
    set_.theta[i] = wrapAngle(pose.theta + std_theta * rng_.gaussian());
  }
  std::fill(set_.w.begin(), set_.w.end(), 1.0);
  lost_ = reset_pending_ = false;
  p_track_ = 1.0 - cfg_.track_hazard;  // a pose given by the user: trusted until the sensors disagree
  restartLikelihoodWatch();
  recover_until_ = -1e300;
  heading_unknown_ = false;
  estimate_.pose = pose;
  computeEstimate();
}

void Filter::setPoseUniform(const Pose2D& pose, double half_xy, double half_theta) {
  set_.resize(cfg_.max_particles);
  for (std::size_t i = 0; i < set_.size(); ++i) {
    double x = pose.x + rng_.uniform(-half_xy, half_xy), y = pose.y + rng_.uniform(-half_xy, half_xy);
    table_->project(x, y);
    set_.x[i] = x;
    set_.y[i] = y;
    set_.theta[i] = wrapAngle(pose.theta + rng_.uniform(-half_theta, half_theta));
  }
  std::fill(set_.w.begin(), set_.w.end(), 1.0);
  lost_ = reset_pending_ = false;
  p_track_ = 1.0 - cfg_.track_hazard;  // a pose given by the user: trusted until the sensors disagree
  restartLikelihoodWatch();
  recover_until_ = -1e300;
  heading_unknown_ = false;
  estimate_.pose = pose;
  computeEstimate();
}

void Filter::globalLocalization() {
  set_.resize(cfg_.max_particles);
  for (std::size_t i = 0; i < set_.size(); ++i) {
    const Pose2D p = table_->sampleFree(rng_);
    set_.x[i] = p.x;
    set_.y[i] = p.y;
    set_.theta[i] = p.theta;
  }
  std::fill(set_.w.begin(), set_.w.end(), 1.0);
  lost_ = reset_pending_ = true;
  heading_unknown_ = cfg_.heading_known_std > 0.0;
  heading_evidence_since_lost_ = false;
  travelled_at_resampling_ = travelled();
  restartLikelihoodWatch();
  computeEstimate();
}

void Filter::update(double now) {
  ctx_.now = now;
  ctx_.quality = estimate_.probability;
  pf_.executeOn(set_, nullptr, nullptr);
  computeEstimate();
}

void Filter::predictAndUpdate(ParticleSet& set) {
  for (auto& a : advancing_) a->advance(set, ctx_);
  const double s0 = set.weightSum();
  bool monitored = false;
  for (std::size_t k = 0; k < checking_.size(); ++k) {
    CheckingInput& c = *checking_[k];
    if (!c.ready(ctx_)) continue;
    c.check(set, ctx_);
    monitored |= c.monitorsLikelihood();
    if (c.measuresHeading()) heading_evidence_since_lost_ = true;
    double predictive, uninformed, nis;
    if (c.evidence(&predictive, &uninformed)) weighEvidence(predictive, uninformed);
    if (c.innovation(&nis)) innovations_.push_back({ctx_.now, nis, k});
  }
  table_->check(set, ctx_);
  const double s1 = set.weightSum();

  if (!(s1 > 0.0) || !std::isfinite(s1)) {
    // Every particle became impossible: lost for sure.
    std::fill(set.w.begin(), set.w.end(), 1.0);
    lost_ = reset_pending_ = true;
    monitored = false;
    if (!resetFromSensorsIfPossible()) globalLocalization();
    return;
  }
  if (monitored && s0 > 0.0) {
    // Augmented MCL's averages of the measurement likelihood; a collapse of the short-term
    // one against the long-term one means the particles no longer explain the data.
    const double w_avg = s1 / s0;
    if (!averages_init_) {
      w_slow_ = w_fast_ = w_avg;
      averages_init_ = true;
    } else {
      // The long-term level is learnt only while tracking: what a good fit looks like.
      if (!lost_) w_slow_ += cfg_.alpha_slow * (w_avg - w_slow_);
      w_fast_ += cfg_.alpha_fast * (w_avg - w_fast_);
    }
    ++monitored_;
    if (!reset_pending_ && monitored_ > cfg_.warmup && w_fast_ < cfg_.lost_ratio * w_slow_) {
      lost_ = reset_pending_ = true;
    }
  }
  while (!innovations_.empty() && innovations_.front().time < ctx_.now - cfg_.contradiction_window)
    innovations_.pop_front();
  if (!lost_ && !reset_pending_ && contradicted()) lost_ = reset_pending_ = true;
  if (reset_pending_ && resetFromSensorsIfPossible()) return;
  if (!reset_pending_) redrawContradictedInputs();
  if (heading_unknown_) watchHeading(set);

  // MRPT's resampling draws from its global generator: seed it from ours so a fixed ~seed
  // replays identically whatever else in the process uses it.
  if (set.ESS() < cfg_.ess_threshold)
    mrpt::random::getRandomGenerator().randomize(static_cast<uint32_t>(rng_.next() >> 32));
}

bool Filter::contradicted() {
  if (cfg_.contradiction_nis <= 0.0 || innovations_.size() < cfg_.contradiction_count) return false;
  std::vector<double> v;
  v.reserve(innovations_.size());
  for (const auto& p : innovations_) v.push_back(p.nis);
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  const double median = v[v.size() / 2];
  if (median > cfg_.contradiction_nis) {
    innovations_.clear();
    return true;
  }
  // A milder disagreement (a slip the odometry did not see): the cloud is right to stay but too
  // tight to move toward the measurements when the robot stands still. Roughen it, as after a
  // reset, while the disagreement lasts.
  if (median > cfg_.roughen_nis) recover_until_ = std::max(recover_until_, ctx_.now + cfg_.contradiction_window);
  return false;
}

void Filter::redrawContradictedInputs() {
  if (cfg_.contradiction_nis <= 0.0 || cfg_.input_contradiction_count == 0) return;
  std::vector<double> v;
  for (std::size_t k = 0; k < checking_.size(); ++k) {
    v.clear();
    for (const auto& p : innovations_)
      if (p.input == k) v.push_back(p.nis);
    if (v.size() < cfg_.input_contradiction_count) continue;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    if (v[v.size() / 2] <= cfg_.contradiction_nis) continue;
    if (!checking_[k]->redraw(set_, ctx_, cfg_.input_reset_fraction)) continue;
    ++input_redraws_;
    innovations_.erase(std::remove_if(innovations_.begin(), innovations_.end(), [k](const Innovation& p) { return p.input == k; }),
                       innovations_.end());
    recover_until_ = std::max(recover_until_, ctx_.now + cfg_.recovery_time);
  }
}

double Filter::travelled() const {
  double d = 0.0;
  for (const auto& a : advancing_) d += a->travelled();
  return d;
}

void Filter::watchHeading(const ParticleSet& set) {
  // Weighted circular spread of the headings: std = sqrt(-2 ln R), R the mean resultant length.
  const double r = headingSpread(set).resultant;
  if (r > 0.0 && std::sqrt(-2.0 * std::log(std::min(r, 1.0))) < cfg_.heading_known_std) heading_unknown_ = false;
}

void Filter::weighEvidence(double predictive, double uninformed) {
  // Two hypotheses: the cloud tracks the true pose (the measurement's density is the cloud's
  // predictive density) or it does not (the measurement could be anything: uninformed density).
  if (!(predictive >= 0.0 && uninformed > 0.0) || !std::isfinite(predictive)) return;
  const double h = cfg_.track_hazard;
  const double prior = p_track_ * (1.0 - h) + (1.0 - p_track_) * h;
  const double num = prior * predictive;
  const double den = num + (1.0 - prior) * uninformed;
  p_track_ = den > 0.0 ? num / den : prior;
}

void Filter::restartLikelihoodWatch() {
  innovations_.clear();
  // A new cloud starts from the known good level: a wrong pose is then detected as a collapse.
  monitored_ = 0;
  w_fast_ = w_slow_;
}

bool Filter::resetFromSensorsIfPossible() {
  PoseSampler* sampler = nullptr;
  for (auto& s : samplers_)
    if (s->canSample(ctx_)) {
      sampler = s.get();
      break;
    }
  if (!sampler) return false;
  const std::size_t n = set_.size();
  const auto replace = static_cast<std::size_t>(std::round(cfg_.reset_fraction * static_cast<double>(n)));
  const double step = replace > 0 ? static_cast<double>(n) / static_cast<double>(replace) : 0.0;
  const double u = rng_.uniform();
  for (std::size_t k = 0; k < replace; ++k) {
    const std::size_t i = std::min(n - 1, static_cast<std::size_t>((static_cast<double>(k) + u) * step));
    const Pose2D p = sampler->sample(ctx_);
    set_.x[i] = p.x;
    set_.y[i] = p.y;
    set_.theta[i] = p.theta;
  }
  std::fill(set_.w.begin(), set_.w.end(), 1.0);
  reset_pending_ = false;
  lost_ = true;  // recovering until the cloud is tight again
  restartLikelihoodWatch();
  ++resets_;
  recover_until_ = ctx_.now + cfg_.recovery_time;
  heading_unknown_ = cfg_.heading_known_std > 0.0 && !sampler->samplesHeading();
  heading_evidence_since_lost_ = false;
  travelled_at_resampling_ = travelled();
  return true;
}

std::size_t Filter::resampledCount(const ParticleSet&, const std::vector<size_t>& picked) {
  ++resamplings_;
  if (!cfg_.adaptive || lost_) return cfg_.max_particles;
  bins_.clear();
  for (size_t i : picked) bins_.add(set_.x[i], set_.y[i], set_.theta[i], cfg_.kld);
  return std::clamp(kldBound(bins_.count(), cfg_.kld), cfg_.min_particles, cfg_.max_particles);
}

void Filter::afterResampling(ParticleSet& set) {
  // Recovering: roughen position and heading (the heading is searched for). Otherwise the
  // position jitter alone keeps a still robot's set from collapsing onto copies of one pose.
  // An unknown heading on a robot that has stood still since it became unknown, with no heading
  // input heard meanwhile: every heading again. Once the robot moved or a compass read, the
  // weights have told headings apart: they are kept (roughened).
  // kStill: below the encoders' noise standing still, above a slow drive's step.
  constexpr double kStill = 0.0005;  // [m]
  const double now_travelled = travelled();
  if (now_travelled - travelled_at_resampling_ >= kStill) heading_evidence_since_lost_ = true;
  travelled_at_resampling_ = now_travelled;
  const bool redraw_headings = heading_unknown_ && !heading_evidence_since_lost_;
  const bool recovering = ctx_.now < recover_until_ || heading_unknown_;
  const double xy = recovering ? cfg_.roughen_xy : cfg_.jitter_xy;
  const double theta = recovering ? cfg_.roughen_theta : 0.0;
  if (xy <= 0.0 && theta <= 0.0 && !redraw_headings) return;
  for (std::size_t i = 0; i < set.size(); ++i) {
    set.x[i] += xy * rng_.gaussian();
    set.y[i] += xy * rng_.gaussian();
    if (redraw_headings) set.theta[i] = rng_.uniform(-M_PI, M_PI);
    else if (theta > 0.0) set.theta[i] = wrapAngle(set.theta[i] + theta * rng_.gaussian());
  }
}

void Filter::computeEstimate() {
  const std::size_t n = set_.size();
  const double* px = set_.x.data();
  const double* py = set_.y.data();
  const double* w = set_.w.data();
  // Heading mean: relative to the previous estimate's heading when the cloud is tight (no
  // trigonometry in the loop), to the circular mean when it is spread (lost).
  const ClusterStats whole = weightedStats(set_, lost_ ? circularMean(set_) : estimate_.pose.theta);
  if (!(whole.weight > 0.0)) return;
  Estimate& e = estimate_;
  e.set_cov = e.cov = whole.cov;
  const auto& c = e.set_cov;
  Pose2D mean = whole.mean;
  e.cluster_weight = 1.0;
  e.clusters = 1;
  // A set narrower than one cell is one cluster: the clustering is only paid for when spread.
  const double bxy = cfg_.cluster_bin_xy, bth = cfg_.cluster_bin_theta;
  if (c[0] > bxy * bxy || c[4] > bxy * bxy || c[8] > bth * bth) {
    const ClusterStats best = clustering_.heaviest(set_);
    mean = best.mean;
    e.cov = best.cov;
    e.cluster_weight = best.weight;
    e.clusters = clustering_.count();
  }
  if (heading_unknown_) {
    // The heaviest cluster's heading is one guess among all: say so (a uniform heading's variance),
    // to rviz and to a respawned HAL resuming from the saved pose.
    for (auto* cov : {&e.cov, &e.set_cov}) {
      (*cov)[2] = (*cov)[5] = (*cov)[6] = (*cov)[7] = 0.0;
      (*cov)[8] = std::max((*cov)[8], M_PI * M_PI / 3.0);
    }
  }
  double x = mean.x, y = mean.y;
  table_->project(x, y);  // the final estimate is possible too
  e.pose = {x, y, mean.theta};
  e.particles = n;
  e.ess = set_.ESS() * static_cast<double>(n);

  // Found again once the whole set converged, not merely its heaviest cluster.
  const double var_xy = 0.5 * (e.set_cov[0] + e.set_cov[4]);
  // An unknown heading is not waited for (see heading_known_std): the position is found.
  if (lost_ && !reset_pending_ && var_xy < cfg_.found_std * cfg_.found_std && (heading_unknown_ || e.set_cov[8] < 0.04)) {
    lost_ = false;
    p_track_ = 0.5;  // converged: whether on the right pose, the next measurements tell
  }
  if (lost_) p_track_ = 0.0;
  // Probability of being within quality_tolerance of the truth: P(tracking) x the cloud's
  // weighted mass within quality_tolerance of the estimate (no Gaussian assumption). Not the
  // likelihood ratio w_fast / w_slow: that one moves with speed and sensor mix, not with error.
  const double tol2 = cfg_.quality_tolerance * cfg_.quality_tolerance;
  double inside = 0.0, sw = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = px[i] - mean.x, dy = py[i] - mean.y;
    sw += w[i];
    if (dx * dx + dy * dy <= tol2) inside += w[i];
  }
  e.tracking = p_track_;
  e.probability = lost_ ? 0.0 : std::clamp(p_track_ * inside / sw, 0.0, 1.0);
  e.lost = lost_;
}

}  // namespace hal_nodes::mcl
