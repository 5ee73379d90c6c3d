// Prints the cost of the HAL devices' per-sample maths (odometry step with two pairs, range
// filter sample, beacon equation, beacon fit over 1000 pairs, drive kinematics), so a
// device's refresh budget can be judged against its rate. Figures only, no pass/fail.
#include <chrono>
#include <cstdio>
#include <random>

#include "hal_nodes/devices/beacons/beacon_equation.h"
#include "hal_nodes/devices/drive/wheel_speeds.h"
#include "hal_nodes/devices/odometry/encoder_tracker.h"
#include "hal_nodes/devices/odometry/wheel_pair.h"
#include "hal_nodes/devices/rangers/range_filter.h"

using namespace hal_nodes;
using Clock = std::chrono::steady_clock;

template <class F>
double nsPer(int n, F&& f) {
  const auto t0 = Clock::now();
  for (int i = 0; i < n; ++i) f(i);
  return std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / n;
}

int main() {
  volatile double sink = 0;
  WheelPairModel m{1.0 / 2328.3, 1.0 / 2328.3, 0.25, 0.01, 0.02, 0.02};
  EncoderTracker l, r, l2, r2;
  PoseIntegrator integ;
  const double odo = nsPer(1000000, [&](int i) {
    const uint32_t a = static_cast<uint32_t>(i * 37), b = static_cast<uint32_t>(i * 41);
    IncrementFusion f;
    f.add(m.increment(l.update(a, 32, 0), r.update(b, 32, 0)), 1.0);
    f.add(m.increment(l2.update(a & 0xffff, 16, 0), r2.update(b & 0xffff, 16, 0)), 0.3);
    integ.add(f.result());
  });
  sink = sink + integ.pose().x;
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(1.0, 0.02);
  RangeFilter filter;
  const double rf = nsPer(1000000, [&](int) { sink = sink + *filter.add(noise(rng), 0.1, 6.0); });
  BeaconEquation eq;
  const double be = nsPer(1000000, [&](int i) { sink = sink + eq.distance(i % 3, 1e-6 * (3000 + i % 5000)); });
  std::vector<double> d, t;
  for (int i = 0; i < 1000; ++i) {
    t.push_back(1e-6 * (1000 + 7 * i));
    d.push_back(343.0 * t.back() + 0.01);
  }
  const double fit = nsPer(1000, [&](int) {
    BeaconEquation e;
    sink = sink + fitEquation(e, t, d, {}).rms;
  });
  const double ws = nsPer(1000000, [&](int i) {
    const WheelSpeeds s = wheelSpeeds(0.3 + 1e-6 * i, 1.0, 0.25, 0.9);
    sink = sink + nativeValue(s.left, 1020.4, 1000) + nativeValue(s.right, 1020.4, 1000);
  });
  std::printf("hal device models (per call, this machine):\n");
  std::printf("  odometry step, 2 pairs (unwrap, model, fuse, integrate + covariance): %8.1f ns\n", odo);
  std::printf("  range filter sample (median of 5 + smoothing):                      %8.1f ns\n", rf);
  std::printf("  beacon delta -> distance:                                           %8.1f ns\n", be);
  std::printf("  beacon equation fit, 1000 pairs:                                    %8.1f us\n", fit / 1e3);
  std::printf("  drive twist -> 2 native wheel commands:                             %8.1f ns\n", ws);
  return sink == 12345.678 ? 1 : 0;
}
