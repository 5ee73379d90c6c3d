// Seeded random streams. Each concern draws from its own stream (seeded from ~seed and the
// stream's name) so that, e.g., how often an emulator reads a ranger never changes the robot's
// trajectory: dynamics stay reproducible whatever the emulators' thread timing.
#pragma once

#include <cstdint>
#include <random>
#include <string>

namespace robot_sim {

class Rng {
 public:
  Rng(unsigned seed, const std::string& stream) : engine_(mix(seed, stream)) {}
  double gaussian(double stddev) { return stddev > 0.0 ? stddev * normal_(engine_) : 0.0; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * unit_(engine_); }
  bool chance(double p) { return p > 0.0 && unit_(engine_) < p; }

 private:
  // FNV-1a over the stream name, mixed with the seed: stable across runs and platforms.
  static uint64_t mix(unsigned seed, const std::string& stream) {
    uint64_t h = 1469598103934665603ull ^ (static_cast<uint64_t>(seed) * 0x9E3779B97F4A7C15ull);
    for (unsigned char c : stream) h = (h ^ c) * 1099511628211ull;
    return h;
  }
  std::mt19937_64 engine_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::uniform_real_distribution<double> unit_{0.0, 1.0};
};

}  // namespace robot_sim
