// Driver benchmark on the kinematic model (driver/kinematic_model.h: one control period of
// command delay, 20 ms motor lag): 20 fixed goto goals chained across the table with the
// product's Autopilot and limiter at 50 Hz and a robot's curves and limits (its config's `hal: driver:`
// block, read by the device's own reader; default config/eurobot2009.yaml), then 200
// cancels at random points of drives. Prints mean time to goal, final position/heading error,
// overshoot, and the cancel-to-stopped time (p50/p99/max).
//   driver_bench [--rate 50] [--delay 1] [--lag 0.02] [--config config/ROBOT.yaml]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "hal_nodes/driver/autopilot.h"
#include "hal_nodes/driver/driver_config.h"
#include "hal_nodes/driver/kinematic_model.h"

using namespace hal_nodes::driver;

namespace {
const Pose2D kGoals[20] = {
    {2.60, 1.70, 0.00}, {0.40, 1.70, M_PI}, {0.40, 0.40, -M_PI / 2}, {2.60, 0.40, 0.0}, {1.50, 1.05, M_PI / 2},
    {1.50, 1.60, M_PI / 2}, {1.00, 1.00, 2.0}, {1.02, 1.01, 2.0}, {2.20, 0.70, -0.7}, {0.70, 1.40, 2.5},
    {2.80, 1.05, 0.0}, {2.30, 1.05, 0.0}, {0.30, 0.30, -2.4}, {1.20, 0.60, 0.3}, {1.80, 1.50, 1.2},
    {0.60, 0.90, -3.0}, {2.50, 1.80, 0.8}, {1.50, 0.30, -1.5}, {1.50, 0.35, -1.5}, {0.35, 1.75, 2.8}};

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(std::ceil(p * v.size())) - 1)];
}
}  // namespace

int main(int argc, char** argv) {
  double rate = 50.0, lag = 0.02;
  int delay = 1;
  std::string config = std::string(ROBOT_CONFIG_DIR) + "/eurobot2009.yaml";
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--rate")) rate = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--delay")) delay = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--lag")) lag = std::atof(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--config")) config = argv[i + 1];
  }
  const double dt = 1.0 / rate;
  AutopilotConfig cfg;
  try {
    cfg = readAutopilotConfig(robot_core::Params::fromYamlFile(config, "hal/driver"),
                              robot_core::RobotGeometry::read(robot_core::Params::fromYamlFile(config, "robot")));
  } catch (const robot_core::ParameterError& e) {
    std::fprintf(stderr, "driver_bench: %s\n", e.what());
    return 2;
  }
  std::printf("config %s: max_wheel_speed %.2f m/s, track_width %.3f m\n", config.c_str(), cfg.limits.max_wheel_speed,
              cfg.limits.track_width);
  KinematicModel robot({0.25, 0.25, 0.0}, delay, lag);
  std::vector<double> times, pos_err, ang_err, overshoot;
  int failed = 0;
  for (const auto& goal : kGoals) {
    Autopilot ap(cfg);
    AutopilotGoal g;
    g.target = goal;
    g.position_tolerance = 0.01;
    g.angle_tolerance = 2.0 * M_PI / 180.0;
    const Pose2D start = robot.pose();
    ap.start(g, start);
    VelocityLimiter lim(cfg.limits);
    const double ux = goal.x - start.x, uy = goal.y - start.y, n = std::hypot(ux, uy);
    double t = 0.0, over = 0.0;
    while (t < 30.0) {
      const Twist2D d = ap.step(robot.pose(), lim.last(), &robot.velocity());  // odometry's twist
      if (ap.done()) break;
      robot.step(lim.apply(d, dt), dt);
      t += dt;
      if (n > 1e-6) over = std::max(over, ((robot.pose().x - goal.x) * ux + (robot.pose().y - goal.y) * uy) / n);
    }
    for (int i = 0; i < 50; ++i) robot.step(Twist2D(), dt);  // settle before measuring
    if (!ap.done()) ++failed;
    times.push_back(t);
    pos_err.push_back(std::hypot(robot.pose().x - goal.x, robot.pose().y - goal.y));
    ang_err.push_back(std::fabs(wrapAngle(robot.pose().theta - goal.theta)));
    overshoot.push_back(over);
  }

  // Cancels: drive toward a far goal, cancel after a random time, measure until the wheels stop.
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> when(0.3, 2.5);
  std::vector<double> stop_times;
  for (int k = 0; k < 200; ++k) {
    KinematicModel r({0.3, 0.3 + 0.005 * k, 0.0}, delay, lag);
    Autopilot ap(cfg);
    AutopilotGoal g;
    g.target = {2.7, 1.0, 0.0};
    ap.start(g, r.pose());
    VelocityLimiter lim(cfg.limits);
    const double cancel_at = when(rng);
    double t = 0.0;
    for (; t < cancel_at; t += dt) r.step(lim.apply(ap.step(r.pose(), lim.last()), dt), dt);
    // Cancel: the device resets the limiter and sends zero at once (within this period).
    lim.reset();
    double s = 0.0;
    while (!r.stopped() && s < 2.0) {
      r.step(lim.last(), dt);
      s += dt;
    }
    stop_times.push_back(s);
  }

  auto mean = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return s / v.size();
  };
  printf("driver bench: KINEMATIC MODEL (no simulator): %.0f Hz control, %d period(s) command delay, %.0f ms motor lag\n",
         rate, delay, 1e3 * lag);
  printf("  goto: %zu goals chained across the table, %d not reached in 30 s\n", times.size(), failed);
  printf("  mean time to goal          %.2f s (max %.2f s)\n", mean(times), *std::max_element(times.begin(), times.end()));
  printf("  final position error       mean %.1f mm, max %.1f mm (tolerance 10 mm)\n", 1e3 * mean(pos_err),
         1e3 * *std::max_element(pos_err.begin(), pos_err.end()));
  printf("  final heading error        mean %.2f deg, max %.2f deg (tolerance 2 deg)\n", mean(ang_err) * 180 / M_PI,
         *std::max_element(ang_err.begin(), ang_err.end()) * 180 / M_PI);
  printf("  overshoot past the goal    mean %.1f mm, max %.1f mm\n", 1e3 * mean(overshoot),
         1e3 * *std::max_element(overshoot.begin(), overshoot.end()));
  printf("  cancel -> wheels stopped   p50 %.0f ms, p99 %.0f ms, max %.0f ms (%zu cancels; zero commanded in the cancel's period)\n",
         1e3 * percentile(stop_times, 0.5), 1e3 * percentile(stop_times, 0.99),
         1e3 * *std::max_element(stop_times.begin(), stop_times.end()), stop_times.size());
  return 0;
}
