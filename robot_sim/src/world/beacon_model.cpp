#include "robot_sim/world/beacon_model.h"

#include <cmath>

namespace robot_sim {

BeaconModel::BeaconModel(const BeaconConfig& config, const std::vector<Point2D>& beacons)
    : config_(config), beacons_(beacons), silent_(beacons.size(), false) {}

double BeaconModel::trueDelta(int i, double x, double y) const {
  const double dx = x - beacons_[i].x, dy = y - beacons_[i].y;
  return std::sqrt(dx * dx + dy * dy + config_.height_delta * config_.height_delta) / config_.speed_of_sound;
}

void BeaconModel::step(double t, const Pose2D& robot, Rng& rng) {
  if (beacons_.empty()) return;
  const double slot = config_.period / static_cast<double>(beacons_.size());
  const double c = std::cos(robot.theta), s = std::sin(robot.theta);
  const double rx = robot.x + c * config_.receiver.x - s * config_.receiver.y;
  const double ry = robot.y + s * config_.receiver.x + c * config_.receiver.y;
  while (static_cast<double>(next_slot_) * slot <= t + 1e-12) {
    const int id = static_cast<int>(next_slot_ % static_cast<long>(beacons_.size()));
    const double stamp = static_cast<double>(next_slot_) * slot;
    ++next_slot_;
    // Draw every random number each slot, so a silent beacon does not shift the others' noise.
    const bool drop = rng.chance(config_.dropout);
    const bool outlier = rng.chance(config_.outlier);
    const double noise = rng.gaussian(config_.noise_std);
    const double wild = rng.uniform(0.0, config_.max_delta);
    if (silent_[id] || drop) continue;
    const double delta = outlier ? wild : trueDelta(id, rx, ry) + noise;
    if (delta < 0.0 || delta > config_.max_delta) continue;  // outside the receiver's window
    queue_.push_back(BeaconMeasurement{id, stamp, delta});
    if (queue_.size() > 256) queue_.pop_front();  // nobody listening: keep the newest
  }
}

std::vector<BeaconMeasurement> BeaconModel::take() {
  std::vector<BeaconMeasurement> out(queue_.begin(), queue_.end());
  queue_.clear();
  return out;
}

void BeaconModel::setSilent(int beacon, bool silent) {
  if (beacon >= 0 && beacon < static_cast<int>(silent_.size())) silent_[beacon] = silent;
}

bool BeaconModel::silent(int beacon) const {
  return beacon >= 0 && beacon < static_cast<int>(silent_.size()) && silent_[beacon];
}

}  // namespace robot_sim
