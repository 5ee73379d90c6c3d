// The localization filter: Monte Carlo Localization on mrpt::bayes::CParticleFilter.
//
// Inputs register themselves (addAdvancing / addChecking); each step MRPT's executeOn() runs:
//   predict/update   every advancing input moves the particles (with motion noise), every
//                    checking input with a new measurement reweights them, the table model
//                    always (impossible poses weigh 0);
//   normalize, ESS   resampling (the selected MRPT scheme) only when ESS < ess_threshold;
//   resampling       the new count follows the KLD bound when adaptive; while the filter is
//                    lost, part of the set is replaced by poses proposed by the sensors.
// Entirely lost: globalLocalization() spreads the particles uniformly over the free table.
// Lost detection (MRPT has none): augmented MCL's short- and long-term averages of the
// measurement likelihood (w_fast, w_slow); when w_fast / w_slow falls below lost_ratio
// (likelihood collapse: kidnapped, or a wrong start) or every particle became impossible, the
// filter declares itself lost and resets from the sensors' proposals (sensor resetting: beacon
// trilateration), falling back to a uniform spread.
// Probability (/mcl/quality): P(the cloud tracks the true pose), a two-state Bayes filter fed
// by each beacon range's predictive density against its density without a pose
// (CheckingInput::evidence), times the cloud's mass within quality_tolerance of the estimate.
// w_fast / w_slow only decide "lost": their ratio moves with speed, sensor mix and the
// intersection weighting, so it is no probability (a good estimate can read ~0.5 while driving).
#pragma once

#include <mrpt/bayes/CParticleFilter.h>

#include <array>
#include <deque>
#include <memory>
#include <vector>

#include "hal_nodes/mcl/checks/table_model.h"
#include "hal_nodes/mcl/clusters.h"
#include "hal_nodes/mcl/input.h"
#include "hal_nodes/mcl/kld.h"
#include "hal_nodes/mcl/particle_set.h"

namespace hal_nodes::mcl {

struct FilterConfig {
  std::size_t max_particles = 2000;
  std::size_t min_particles = 200;
  bool adaptive = false;  // KLD count between min and max
  KldParams kld;
  mrpt::bayes::CParticleFilter::TParticleResamplingAlgorithm resampling =
      mrpt::bayes::CParticleFilter::prSystematic;
  double ess_threshold = 0.5;  // resample when ESS/N < this
  double alpha_slow = 0.01;    // likelihood averages (per monitored measurement)
  double alpha_fast = 0.2;
  double lost_ratio = 0.05;    // w_fast / w_slow below this: lost
  std::size_t warmup = 30;     // monitored measurements before the collapse test is armed
  double reset_fraction = 1.0; // share of the set replaced by sensor proposals when lost
  double found_std = 0.05;     // [m] cloud spread below which a reset counts as converged
  // After a reset the heading is only known from motion: for recovery_time, every resampling
  // roughens the set (jitter) so the cloud keeps enough heading diversity to find the right one.
  double recovery_time = 2.0;  // [s]
  double roughen_xy = 0.003;   // [m]
  double roughen_theta = 0.02; // [rad]
  // Position jitter at every resampling, recovering or not. Resampling a robot that stands still
  // only copies particles (no motion noise spreads them), and a cloud of copies of one pose cannot
  // follow the beacons to a pose it never held: a push of a few centimetres would stay uncorrected.
  // Position only: standing still, the beacons pin the position but not the heading.
  double jitter_xy = 0.002;    // [m]
  double quality_tolerance = 0.05;  // [m] "right" means within this of the truth
  // Probability of a change between tracking and not tracking per measurement with evidence
  // (kidnap, slip): keeps the tracking probability from saturating, so it can fall quickly.
  // 1e-4: two garbage ranges in a row (outlier_probability each) leave it above 0.9, four
  // inconsistent ones after a kidnap take it under 0.1. A much larger hazard lets two garbage
  // ranges in a row drop it far enough to abort the driver's goal.
  double track_hazard = 1e-4;
  // Kidnap: lost when, over the last contradiction_window seconds of measurements, at least
  // contradiction_count measurements came and their median normalized innovation (input.h) is
  // above contradiction_nis: most measurements contradict the cloud, not one beacon's echo.
  // 0 disables. The likelihood averages cannot tell (not monitored: see the top of this file),
  // and a kidnapped cloud rarely becomes impossible on the table.
  double contradiction_nis = 9.0;      // (3 sigma)
  double contradiction_window = 1.0;   // [s]
  std::size_t contradiction_count = 10;
  double roughen_nis = 2.0;            // median above it (not yet lost): roughen the set meanwhile
  // One input against the rest: when at least input_contradiction_count of one input's own
  // measurements came in the window and their median is above contradiction_nis, without the
  // whole set's median calling for a reset, that input redraws what it measures (input.h) in
  // input_reset_fraction of the set. A slip that turned the estimate leaves the position right:
  // the beacons agree and outvote the compass, whose every reading says "wrong". (The others
  // may also be silent: the rest of the set keeps its heading, for them to judge later.)
  std::size_t input_contradiction_count = 5;
  double input_reset_fraction = 0.5;
  // After a reset whose headings were drawn uniformly (beacon ranges give positions only), the
  // heading is unknown until the weighted set's heading spread falls below heading_known_std
  // (motion, or a heading input, told the headings apart). Meanwhile, until the robot first
  // moves or a heading input measures, each resampling redraws every heading uniformly (standing
  // still, nothing has told them apart, and copies drifting to one heading would make a confident
  // wrong estimate); the set is roughened as while recovering; and "found" is judged on the
  // position alone (the driver may move, and moving resolves the heading). 0 disables.
  double heading_known_std = 0.1;      // [rad]
  // The estimate is the heaviest cluster's (clusters.h) once the set spreads wider than one cell.
  double cluster_bin_xy = 0.10;    // [m]
  double cluster_bin_theta = 0.20; // [rad]
  uint64_t seed = 1;
};

// Parse a resampling scheme name: multinomial, residual, stratified, systematic.
bool parseResampling(const std::string& name, mrpt::bayes::CParticleFilter::TParticleResamplingAlgorithm* out);

struct Estimate {
  Pose2D pose;                   // the heaviest particle cluster's weighted mean
  std::array<double, 9> cov{};   // x, y, theta (row-major): that cluster's covariance
  std::array<double, 9> set_cov{};  // the whole set's (what amcl reports; wrong when multimodal)
  double cluster_weight = 1.0;   // the cluster's share of the set's weight
  std::size_t clusters = 1;
  // That the estimate is within quality_tolerance of the truth: P(the filter tracks the true
  // pose | the measurements' evidence) x the cloud's mass within quality_tolerance of the estimate.
  double probability = 0.0;
  double tracking = 0.0;         // the first factor
  bool lost = true;
  std::size_t particles = 0;
  double ess = 0.0;              // effective sample size (particles)
};

class Filter : private ParticleSet::Hooks {
 public:
  Filter(const FilterConfig& cfg, std::shared_ptr<TableModel> table);
  Filter(const Filter&) = delete;
  Filter& operator=(const Filter&) = delete;

  void addAdvancing(std::shared_ptr<AdvancingInput> input);
  void addChecking(std::shared_ptr<CheckingInput> input);
  // An input that can propose poses when lost (also registered as checking input if it is one).
  void addSampler(std::shared_ptr<PoseSampler> sampler);

  // A Gaussian cloud around a known pose (start position, rviz /initialpose).
  void setPose(const Pose2D& pose, double std_xy, double std_theta);
  // A cloud uniform within +-half_xy, +-half_theta of a pose.
  void setPoseUniform(const Pose2D& pose, double half_xy, double half_theta);
  // Entirely lost: uniform over the free table, every heading; recovery from the sensors.
  void globalLocalization();

  // One filter step at time `now` [s]: applies what the inputs hold, updates the estimate.
  void update(double now);

  const Estimate& estimate() const { return estimate_; }
  const ParticleSet& particles() const { return set_; }
  const FilterConfig& config() const { return cfg_; }
  const TableModel& table() const { return *table_; }
  unsigned long resamplings() const { return resamplings_; }
  unsigned long resets() const { return resets_; }
  unsigned long inputRedraws() const { return input_redraws_; }
  bool headingUnknown() const { return heading_unknown_; }
  double wSlow() const { return w_slow_; }
  double wFast() const { return w_fast_; }

 private:
  // ParticleSet::Hooks
  void predictAndUpdate(ParticleSet& set) override;
  std::size_t resampledCount(const ParticleSet& set, const std::vector<size_t>& picked) override;
  double uniform() override { return rng_.uniform(); }
  void afterResampling(ParticleSet& set) override;

  bool resetFromSensorsIfPossible();
  void weighEvidence(double predictive, double uninformed);
  void restartLikelihoodWatch();
  void computeEstimate();

  FilterConfig cfg_;
  std::shared_ptr<TableModel> table_;
  ParticleSet set_;
  mrpt::bayes::CParticleFilter pf_;
  Rng rng_;
  BinCounter bins_;
  std::vector<std::shared_ptr<AdvancingInput>> advancing_;
  std::vector<std::shared_ptr<CheckingInput>> checking_;
  std::vector<std::shared_ptr<PoseSampler>> samplers_;
  StepContext ctx_;
  Estimate estimate_;
  Clustering clustering_;
  double w_slow_ = 0.0, w_fast_ = 0.0;
  double p_track_ = 0.0;          // P(tracking the true pose), a two-state Bayes filter on the evidence
  std::size_t monitored_ = 0;     // monitored measurements since the last (re)start
  bool averages_init_ = false;
  bool lost_ = true;
  bool reset_pending_ = false;
  double recover_until_ = -1e300;  // roughen after resampling until then
  bool heading_unknown_ = false;    // see heading_known_std
  bool heading_evidence_since_lost_ = false;  // the robot moved, or a heading input measured
  double travelled_at_resampling_ = 0.0;
  struct Innovation {
    double time;
    double nis;          // normalized innovation squared
    std::size_t input;   // index in checking_
  };
  std::deque<Innovation> innovations_;
  bool contradicted();
  void redrawContradictedInputs();
  double travelled() const;
  void watchHeading(const ParticleSet& set);
  unsigned long resamplings_ = 0, resets_ = 0, input_redraws_ = 0;
};

}  // namespace hal_nodes::mcl
