// mcl_bench RUN.csv PARTICLES track|global [--kld] [--seed N] [--jitter M] [--table LENGTH WIDTH]
// Runs the localization device's own filter (libhal_mcl, the code the node links) on a
// synthetic beacon run and prints one line in the format of scripts/bench/data/README.md.
// Parameters are the node's defaults (config/<robot>.yaml `hal: localization:` block), so
// the figures are those of the product, not of a bench-only tuning.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include "hal_nodes/mcl/mcl.h"
#include "mcl_bench_common.h"

using namespace hal_nodes::mcl;

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: mcl_bench RUN.csv PARTICLES track|global [--kld] [--seed N] [--jitter M] [--table LENGTH WIDTH]\n");
    return 2;
  }
  const std::string path = argv[1], mode = argv[3];
  const long particles = std::strtol(argv[2], nullptr, 10);
  if (particles < 1 || (mode != "track" && mode != "global")) {
    std::fprintf(stderr, "mcl_bench: PARTICLES must be >= 1 and the mode track or global\n");
    return 2;
  }
  bool kld = false;
  uint64_t seed = 1;
  double jitter = FilterConfig{}.jitter_xy;  // [m] ~jitter_xy: compare a run with and without it
  double length = 3.0, width = 2.1;
  for (int i = 4; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--kld")) kld = true;
    else if (!std::strcmp(argv[i], "--seed") && i + 1 < argc) seed = std::strtoull(argv[++i], nullptr, 10);
    else if (!std::strcmp(argv[i], "--jitter") && i + 1 < argc) jitter = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--table") && i + 2 < argc) {
      length = std::atof(argv[++i]);
      width = std::atof(argv[++i]);
    } else {
      std::fprintf(stderr, "mcl_bench: unknown option %s\n", argv[i]);
      return 2;
    }
  }
  mcl_bench::Run run;
  try {
    run = mcl_bench::readRun(path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mcl_bench: %s\n", e.what());
    return 1;
  }

  auto table = std::make_shared<TableModel>(length, width, 0.0);
  FilterConfig fc;
  fc.max_particles = static_cast<std::size_t>(particles);
  fc.min_particles = std::min<std::size_t>(fc.min_particles, fc.max_particles);
  fc.adaptive = kld;
  fc.seed = seed;
  fc.jitter_xy = jitter;
  Filter filter(fc, table);
  MotionModel mm;
  auto odom = std::make_shared<OdometryInput>(std::vector<OdometryInput::Pair>{{"wheels", 1.0}}, mm);
  BeaconBeltsConfig bc;
  for (const auto& b : run.beacons) bc.beacons.push_back({b.first, b.second});
  bc.range_std_auto = true;
  auto beacons = std::make_shared<BeaconBelts>(bc, table);
  filter.addAdvancing(odom);
  filter.addChecking(beacons);
  filter.addSampler(beacons);

  if (mode == "track")
    filter.setPoseUniform({run.start_x, run.start_y, run.start_theta}, 0.02, 0.02);
  else
    filter.globalLocalization();

  mcl_bench::Score score;
  FILE* dump = std::getenv("MCL_BENCH_DUMP") ? std::fopen(std::getenv("MCL_BENCH_DUMP"), "w") : nullptr;
  for (const auto& r : run.rows) {
    const auto t0 = std::chrono::steady_clock::now();
    odom->addIncrement(0, {r.odo_dx, r.odo_dy, r.odo_dtheta}, r.t);  // stamped: slips are found
    if (r.beacon_id >= 0) beacons->addRange(r.t, r.beacon_id, r.range);
    filter.update(r.t);
    const Pose2D p = filter.estimate().pose;
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    score.add(r, p.x, p.y, p.theta, ms);
    if (dump) std::fprintf(dump, "%.2f %.5f %.5f %.5f %.5f %.5f %.5f\n", r.t, p.x, p.y, p.theta, r.true_x, r.true_y, r.true_theta);
  }
  score.print(mode, static_cast<std::size_t>(particles));
  if (std::getenv("MCL_BENCH_VERBOSE"))
    std::fprintf(stderr, "resamplings %lu resets %lu learned_range_std %.4f final_particles %zu slips %zu\n", filter.resamplings(),
                 filter.resets(), beacons->learnedStd(), filter.particles().size(), odom->slips());
  return 0;
}
