// The particle set, plugged into MRPT's particle filter as a CParticleFilterCapable.
//
// Why not CParticleFilterData<T>: MRPT's generic storage is a std::deque of particles with a
// dynamic_cast per weight access and an exp() per particle in ESS(); this set keeps plain
// arrays (structure of arrays, linear weights scaled so the largest is 1) and never allocates
// in the particle loop. mrpt::bayes::CParticleFilter still drives each step (predict/update,
// normalize, ESS test, resampling with the selected MRPT scheme); the filter's own work is
// reached through Hooks, and resampling hands the surviving indices to the hooks so the
// particle count can adapt (KLD) and recovery particles can be injected.
#pragma once

#include <mrpt/bayes/CParticleFilterCapable.h>

#include <cstddef>
#include <vector>

namespace hal_nodes::mcl {

class ParticleSet : public mrpt::bayes::CParticleFilterCapable {
 public:
  // What the filter does inside MRPT's step.
  class Hooks {
   public:
    virtual ~Hooks() = default;
    // Move every particle (advancing inputs) and reweight it (checking inputs).
    virtual void predictAndUpdate(ParticleSet& set) = 0;
    // How many particles the resampled set should hold, given the surviving indices.
    virtual std::size_t resampledCount(const ParticleSet& set, const std::vector<size_t>& picked) = 0;
    // A uniform number in [0, 1) from the filter's seeded generator (systematic thinning).
    virtual double uniform() = 0;
    // Called once the set was replaced by the resampled one (equal weights).
    virtual void afterResampling(ParticleSet& set) = 0;
  };

  std::vector<double> x, y, theta;  // pose of each particle in the map frame
  std::vector<double> w;            // linear weight, the largest scaled to 1 after normalizeWeights()

  void setHooks(Hooks* hooks) { hooks_ = hooks; }
  std::size_t size() const { return x.size(); }
  void resize(std::size_t n);
  double weightSum() const;
  // ESS as a fraction of the particle count, in [0, 1] (what MRPT compares with BETA).
  double essFraction() const { return ESS(); }

  // ---- mrpt::bayes::CParticleFilterCapable (log weights at the interface) ----
  double getW(size_t i) const override;
  void setW(size_t i, double log_w) override;
  size_t particlesCount() const override { return x.size(); }
  double normalizeWeights(double* out_max_log_w = nullptr) override;
  double ESS() const override;
  void performSubstitution(const std::vector<size_t>& indx) override;

 protected:
  // MRPT calls this for pfStandardProposal; the action and observation come through the
  // registered inputs instead (they may be null).
  void prediction_and_update_pfStandardProposal(const mrpt::obs::CActionCollection* action,
                                                const mrpt::obs::CSensoryFrame* observation,
                                                const mrpt::bayes::CParticleFilter::TParticleFilterOptions& options) override;

 private:
  Hooks* hooks_ = nullptr;
  std::vector<double> nx_, ny_, nt_;  // scratch for substitution, reused
};

}  // namespace hal_nodes::mcl
