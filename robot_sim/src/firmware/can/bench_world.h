// A bench-top stand-in for the simulated world, for CAN emulators hosted without one
// (firmware_host, the CAN rostests and benchmarks): the boards on a test bench, wheels in the
// air. Motors turn their encoders at `fraction * bench_ticks_per_s`, servos and steppers reach
// their targets (steppers at 2000 steps/s between 0 and 20000 steps, with <name>_min/_max end
// switches closed at the limits), rangers see `bench_range` metres, the switches named in
// `bench_closed` are closed, others open.
// In the simulator the emulators get the real World (robot_sim/world) instead.
#pragma once

#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "robot_sim/world/world.h"

namespace robot_sim {

class BenchWorld : public World {
 public:
  BenchWorld(double ticks_per_s, double range_m, std::vector<std::string> closed = {})
      : ticks_per_s_(ticks_per_s), range_m_(range_m), closed_(std::move(closed)) {}

  double time() const override {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  void setMotorCommand(const std::string& motor, double fraction) override {
    std::lock_guard<std::mutex> lk(mutex_);
    Motor& m = advance(motor);
    m.fraction = std::max(-1.0, std::min(1.0, fraction));
  }
  double motorCurrent(const std::string& motor) const override {
    std::lock_guard<std::mutex> lk(mutex_);
    auto it = motors_.find(motor);
    return it == motors_.end() ? 0.0 : 0.5 * std::fabs(it->second.fraction);
  }
  void setServoTarget(const std::string& servo, double position) override {
    std::lock_guard<std::mutex> lk(mutex_);
    servos_[servo] = position;
  }
  double servoPosition(const std::string& servo) const override {
    std::lock_guard<std::mutex> lk(mutex_);
    auto it = servos_.find(servo);
    return it == servos_.end() ? 0.0 : it->second;
  }
  void setStepperTarget(const std::string& stepper, int64_t steps) override {
    std::lock_guard<std::mutex> lk(mutex_);
    Stepper& s = advanceStepper(stepper);
    s.target = std::max<int64_t>(0, std::min<int64_t>(kStepperMax, steps));
  }
  int64_t stepperPosition(const std::string& stepper) const override {
    std::lock_guard<std::mutex> lk(mutex_);
    return const_cast<BenchWorld*>(this)->advanceStepper(stepper).position;
  }
  int64_t encoderTicks(const std::string& encoder) const override {
    std::lock_guard<std::mutex> lk(mutex_);
    return static_cast<int64_t>(std::llround(const_cast<BenchWorld*>(this)->advance(encoder).ticks));
  }
  double measureRange(const std::string&) override { return range_m_; }
  double measureCompassDeg() override { return 0.0; }
  bool switchClosed(const std::string& name) const override {
    const auto ends = [&](const char* suffix) {
      const std::string s(suffix);
      return name.size() > s.size() && name.compare(name.size() - s.size(), s.size(), s) == 0;
    };
    if (ends("_min")) return stepperPosition(name.substr(0, name.size() - 4)) <= 0;
    if (ends("_max")) return stepperPosition(name.substr(0, name.size() - 4)) >= kStepperMax;
    for (const auto& c : closed_)
      if (c == name) return true;
    return false;
  }
  double batteryVoltage() const override { return 24.0; }
  std::vector<BeaconMeasurement> takeBeaconMeasurements() override { return {}; }
  WorldSnapshot snapshot() const override {
    WorldSnapshot s;
    s.time = time();
    return s;
  }

 private:
  static constexpr int64_t kStepperMax = 20000;
  static constexpr double kStepperSpeed = 2000.0;  // [steps/s]
  struct Motor {
    double fraction = 0.0, ticks = 0.0, t = -1.0;
  };
  struct Stepper {
    int64_t position = 0, target = 0;
    double t = -1.0;
  };
  Motor& advance(const std::string& name) {
    Motor& m = motors_[name];
    const double now = time();
    if (m.t >= 0) m.ticks += m.fraction * ticks_per_s_ * (now - m.t);
    m.t = now;
    return m;
  }
  Stepper& advanceStepper(const std::string& name) {
    Stepper& s = steppers_[name];
    const double now = time();
    if (s.t >= 0) {
      const int64_t step = static_cast<int64_t>(kStepperSpeed * (now - s.t));
      if (step > 0) {
        const int64_t d = s.target - s.position;
        s.position += d > 0 ? std::min(d, step) : std::max(d, -step);
        s.t = now;
      }
    } else {
      s.t = now;
    }
    return s;
  }

  const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  double ticks_per_s_;
  double range_m_;
  std::vector<std::string> closed_;
  mutable std::mutex mutex_;
  std::map<std::string, Motor> motors_;
  std::map<std::string, double> servos_;
  std::map<std::string, Stepper> steppers_;
};

}  // namespace robot_sim
