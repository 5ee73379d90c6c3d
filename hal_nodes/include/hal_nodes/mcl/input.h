// The two kinds of inputs the filter knows: an input registers itself with the filter and
// interprets its own data, so a new sensor is a new class and the filter does not change.
//   AdvancingInput  moves the particles (odometry), with noise from its motion model.
//   CheckingInput   reweights the particles by the likelihood of its latest measurement,
//                   raised to its configured reliability in [0, 1] (0: ignored, 1: trusted).
//   PoseSampler     an input that can also propose poses from its data alone, used to recover
//                   when the filter is lost (sensor resetting).
#pragma once

#include <cmath>
#include <string>
#include <utility>

#include "hal_nodes/mcl/particle_set.h"
#include "hal_nodes/mcl/pose.h"
#include "hal_nodes/mcl/rng.h"

namespace hal_nodes::mcl {

// What the filter tells its inputs about the current step.
struct StepContext {
  double now = 0.0;      // [s] time of the step (measurement stamps are compared with it)
  double quality = 0.0;  // the filter's current probability of being right, 0..1
  Rng* rng = nullptr;
};

class AdvancingInput {
 public:
  explicit AdvancingInput(std::string name) : name_(std::move(name)) {}
  virtual ~AdvancingInput() = default;
  const std::string& name() const { return name_; }
  // Move every particle by the motion accumulated since the last call (no-op if none).
  virtual void advance(ParticleSet& set, const StepContext& ctx) = 0;
  // The distance the robot has travelled by this input so far [m] (translation, not rotation):
  // whether the robot moved between two steps.
  virtual double travelled() const { return 0.0; }

 private:
  std::string name_;
};

class CheckingInput {
 public:
  CheckingInput(std::string name, double reliability) : name_(std::move(name)), reliability_(reliability) {}
  virtual ~CheckingInput() = default;
  const std::string& name() const { return name_; }
  double reliability() const { return reliability_; }
  // Whether a measurement waits to be applied at this step.
  virtual bool ready(const StepContext& ctx) const = 0;
  // Multiply each particle's weight by its likelihood^reliability, then consume the measurement.
  virtual void check(ParticleSet& set, const StepContext& ctx) = 0;
  // True for inputs whose likelihood tracks whether the filter is lost (w_slow/w_fast).
  virtual bool monitorsLikelihood() const { return false; }
  // True for inputs that measure the heading on their own (a compass), without motion.
  virtual bool measuresHeading() const { return false; }
  // After check(): the density of the measurement just applied under the cloud (prior-weighted
  // mean of its untempered likelihood) and its density if the pose were unknown. Their ratio is
  // the evidence that the filter tracks the true pose. False: this input gives no such evidence.
  virtual bool evidence(double* /*predictive*/, double* /*uninformed*/) const { return false; }
  // After check(): the measurement's normalized innovation squared against the cloud (its
  // residual from the cloud's mean prediction, squared, over its noise variance plus the
  // prediction's spread): ~1 when the cloud explains it. False: this input gives none.
  virtual bool innovation(double* /*nis*/) const { return false; }
  // Drop pending data (on reset).
  virtual void clear() {}
  // This input's own measurements contradict the cloud while the others agree (a compass after a
  // slip that turned the estimate, outvoted by the beacons): replace what it measures in
  // `fraction` of the set by draws from its latest measurement alone. False: it cannot.
  virtual bool redraw(ParticleSet& /*set*/, const StepContext& /*ctx*/, double /*fraction*/) { return false; }

 protected:
  // likelihood^reliability without a pow() when reliability is 1.
  double tempered(double likelihood) const {
    return reliability_ == 1.0 ? likelihood : std::pow(likelihood, reliability_);
  }

 private:
  std::string name_;
  double reliability_;
};

class PoseSampler {
 public:
  virtual ~PoseSampler() = default;
  // Whether the data now allows proposing poses.
  virtual bool canSample(const StepContext& ctx) const = 0;
  // A pose drawn from the data alone (heading may be drawn uniformly when unobserved).
  virtual Pose2D sample(const StepContext& ctx) = 0;
  // Whether the proposals' headings are measured; false: drawn uniformly (beacon ranges give
  // positions only), and only motion or a heading input can tell them apart afterwards.
  virtual bool samplesHeading() const { return false; }
};

}  // namespace hal_nodes::mcl
