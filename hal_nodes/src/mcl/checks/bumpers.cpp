#include "hal_nodes/mcl/checks/bumpers.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hal_nodes::mcl {

Bumpers::Bumpers(const std::vector<BumperConfig>& bumpers, const BumpersOptions& opts, std::shared_ptr<const TableModel> table)
    : CheckingInput("bumpers", opts.reliability), bumpers_(bumpers), opts_(opts), table_(std::move(table)) {
  if (!table_) throw std::invalid_argument("bumpers: a table model is needed");
  if (!(opts_.tolerance >= 0.0 && opts_.std > 0.0)) throw std::invalid_argument("bumpers: tolerance >= 0 and std > 0");
  if (!(opts_.other_probability >= 0.0 && opts_.other_probability < 1.0))
    throw std::invalid_argument("bumpers: other_probability must be in [0, 1)");
  if (!(opts_.reliability >= 0.0 && opts_.reliability <= 1.0)) throw std::invalid_argument("bumpers: reliability must be in [0, 1]");
}

void Bumpers::setClosed(double stamp, const std::vector<std::string>& closed) {
  std::vector<std::size_t> now;
  for (const auto& name : closed) {
    auto it = std::find_if(bumpers_.begin(), bumpers_.end(), [&](const BumperConfig& b) { return b.name == name; });
    if (it == bumpers_.end()) {
      ++unknown_;
      continue;
    }
    now.push_back(static_cast<std::size_t>(it - bumpers_.begin()));
  }
  std::sort(now.begin(), now.end());
  changed_ = changed_ || now != closed_;
  closed_ = now;
  (void)stamp;
}

bool Bumpers::ready(const StepContext& ctx) const {
  if (closed_.empty()) return false;
  return changed_ || ctx.now - last_applied_ >= opts_.min_interval;
}

double Bumpers::likelihood(const Pose2D& pose) const {
  double p = 1.0;
  for (std::size_t k : closed_) {
    const Pose2D contact = compose(pose, {bumpers_[k].x, bumpers_[k].y, 0.0});
    const double d = std::max(0.0, table_->geometry().distanceToEdge(contact.x, contact.y) - opts_.tolerance);
    p *= (1.0 - opts_.other_probability) * std::exp(-0.5 * d * d / (opts_.std * opts_.std)) + opts_.other_probability;
  }
  return p;
}

void Bumpers::check(ParticleSet& set, const StepContext& ctx) {
  changed_ = false;
  last_applied_ = ctx.now;
  for (std::size_t i = 0; i < set.size(); ++i)
    if (set.w[i] > 0.0) set.w[i] *= tempered(likelihood({set.x[i], set.y[i], set.theta[i]}));
}

}  // namespace hal_nodes::mcl
