// One pair of encoders on a differential axis (the driven wheels, or undriven measuring
// wheels): converts tick increments into an odometry increment with its noise. The noise
// model is a random walk: the variance of the distance grows with |distance|, the variance
// of the heading with |distance| (scrub, diameter mismatch) and with |rotation| (track width).
#pragma once

#include <cstdint>

#include "hal_nodes/devices/odometry/pose_integrator.h"

namespace hal_nodes {

struct WheelPairModel {
  double left_m_per_tick = 0.0;   // signed: a negative value flips a mirrored encoder
  double right_m_per_tick = 0.0;
  double track_width = 0.0;       // [m] distance between the two wheels' contact points
  double distance_noise = 0.01;   // [m/sqrt(m)]: std of distance after 1 m
  double heading_noise = 0.01;    // [rad/sqrt(m)]: std of heading after 1 m straight
  double rotation_noise = 0.01;   // [rad/sqrt(rad)]: std of heading after a 1 rad turn

  OdometryIncrement increment(double left_ticks, double right_ticks) const;  // ticks may be fractional (interpolated)
};

// Fuse the increments of several pairs, each with a reliability weight (> 0): the weighted
// mean of the increments, with the weighted mean of their variances (pairs share the same
// floor and the same slip, so their errors are not independent: no variance reduction).
class IncrementFusion {
 public:
  void add(const OdometryIncrement& inc, double weight);
  bool empty() const { return weight_ <= 0.0; }
  OdometryIncrement result() const;

 private:
  OdometryIncrement sum_;
  double weight_ = 0.0;
};

}  // namespace hal_nodes
