// The three fixed beacons transmit ultrasonic pulses in turn, one per transmit slot
// (period / n_beacons); the receiver on the robot measures each pulse's time of flight.
// Some slots give nothing (dropout), some a random value (outlier, e.g. an echo).
#pragma once

#include <deque>
#include <vector>

#include "robot_sim/world/config.h"
#include "robot_sim/world/random.h"

namespace robot_sim {

class BeaconModel {
 public:
  BeaconModel(const BeaconConfig& config, const std::vector<Point2D>& beacons);

  // Emits the measurements of every slot that fell in (t - dt, t] for a robot at `robot`.
  void step(double t, const Pose2D& robot, Rng& rng);
  std::vector<BeaconMeasurement> take();

  // Fault injection: a silent beacon transmits nothing.
  void setSilent(int beacon, bool silent);
  bool silent(int beacon) const;
  std::size_t count() const { return beacons_.size(); }

  // The noiseless time of flight from beacon i to a receiver at (x, y).
  double trueDelta(int beacon, double x, double y) const;

 private:
  BeaconConfig config_;
  std::vector<Point2D> beacons_;
  std::vector<bool> silent_;
  long next_slot_ = 0;
  std::deque<BeaconMeasurement> queue_;
};

}  // namespace robot_sim
