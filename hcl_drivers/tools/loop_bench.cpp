// loop_bench RATE SECONDS: runs one LoopScheduler loop at RATE Hz for SECONDS (wall time)
// and prints the achieved rate and the period error distribution.
#include <ros/time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <thread>
#include <vector>

#include "hcl_drivers/loop_scheduler.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: loop_bench RATE_HZ SECONDS\n");
    return 2;
  }
  const double rate = std::atof(argv[1]);
  const double seconds = std::atof(argv[2]);
  if (!(rate > 0) || !(seconds > 0)) {
    std::fprintf(stderr, "loop_bench: RATE_HZ and SECONDS must be > 0\n");
    return 2;
  }
  ros::Time::init();
  std::vector<double> stamps;
  stamps.reserve(static_cast<std::size_t>(rate * seconds * 1.5) + 16);
  std::mutex m;
  hcl_drivers::LoopScheduler scheduler;
  scheduler.join("", "bench", rate, [&] {
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    std::lock_guard<std::mutex> lk(m);
    stamps.push_back(t);
  });
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  scheduler.leave("bench");
  std::vector<double> err;
  for (std::size_t i = 1; i < stamps.size(); ++i) err.push_back(std::fabs(stamps[i] - stamps[i - 1] - 1.0 / rate));
  std::sort(err.begin(), err.end());
  auto pct = [&](double p) { return err.empty() ? 0.0 : err[std::min(err.size() - 1, static_cast<std::size_t>(p * err.size()))]; };
  const double span = stamps.size() > 1 ? stamps.back() - stamps.front() : 0.0;
  std::printf("loop configured_hz %.0f achieved_hz %.2f p50_jitter_us %.1f p99_jitter_us %.1f max_jitter_us %.1f\n", rate,
              span > 0 ? (stamps.size() - 1) / span : 0.0, 1e6 * pct(0.5), 1e6 * pct(0.99), 1e6 * (err.empty() ? 0.0 : err.back()));
  return 0;
}
