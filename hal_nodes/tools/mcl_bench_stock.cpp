// mcl_bench_stock RUN.csv PARTICLES track|global [--range-std M] [--tuned-motion] [--seed N] [--table LENGTH WIDTH]
// The reference peer of mcl_bench: MRPT's stock 2D MCL (CMonteCarloLocalization2D with a
// CBeaconMap likelihood, standard proposal, MRPT's default Gaussian odometry model, systematic
// resampling when ESS < 0.5, fixed particle count) on the same synthetic beacon run, printing
// the same one-line format (scripts/bench/data/README.md). --range-std sets CBeaconMap's
// likelihoodOptions.rangeStd (the only thing that sets its beacon noise; default 0.08 m).
#include <mrpt/bayes/CParticleFilter.h>
#include <mrpt/maps/CBeacon.h>
#include <mrpt/maps/CBeaconMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationBeaconRanges.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPoint3D.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/random/RandomGenerators.h>
#include <mrpt/slam/CMonteCarloLocalization2D.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "mcl_bench_common.h"

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: mcl_bench_stock RUN.csv PARTICLES track|global [--range-std M] [--tuned-motion] [--seed N] [--table LENGTH WIDTH]\n");
    return 2;
  }
  const std::string path = argv[1], mode = argv[3];
  const long particles = std::strtol(argv[2], nullptr, 10);
  if (particles < 1 || (mode != "track" && mode != "global")) {
    std::fprintf(stderr, "mcl_bench_stock: PARTICLES must be >= 1 and the mode track or global\n");
    return 2;
  }
  double range_std = 0.08, length = 3.0, width = 2.1;
  unsigned seed = 1;
  bool tuned = false;
  for (int i = 4; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--range-std") && i + 1 < argc) range_std = std::atof(argv[++i]);
    else if (!std::strcmp(argv[i], "--tuned-motion")) tuned = true;
    else if (!std::strcmp(argv[i], "--seed") && i + 1 < argc) seed = static_cast<unsigned>(std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--table") && i + 2 < argc) {
      length = std::atof(argv[++i]);
      width = std::atof(argv[++i]);
    } else {
      std::fprintf(stderr, "mcl_bench_stock: unknown option %s\n", argv[i]);
      return 2;
    }
  }
  mcl_bench::Run run;
  try {
    run = mcl_bench::readRun(path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mcl_bench_stock: %s\n", e.what());
    return 1;
  }
  mrpt::random::getRandomGenerator().randomize(seed);

  auto map = mrpt::maps::CBeaconMap::Create();
  for (std::size_t id = 0; id < run.beacons.size(); ++id) {
    mrpt::maps::CBeacon b;
    b.m_ID = static_cast<mrpt::maps::CBeacon::TBeaconID>(id);
    b.m_typePDF = mrpt::maps::CBeacon::pdfGauss;
    b.m_locationGauss.mean = mrpt::poses::CPoint3D(run.beacons[id].first, run.beacons[id].second, 0.0);
    b.m_locationGauss.cov.setZero();
    map->push_back(b);
  }
  map->likelihoodOptions.rangeStd = range_std;

  mrpt::slam::CMonteCarloLocalization2D pdf(static_cast<size_t>(particles));
  pdf.options.metricMap = map;
  if (mode == "track")
    pdf.resetUniform(run.start_x - 0.02, run.start_x + 0.02, run.start_y - 0.02, run.start_y + 0.02,
                     run.start_theta - 0.02, run.start_theta + 0.02, static_cast<int>(particles));
  else
    pdf.resetUniform(0.0, length, 0.0, width, -M_PI, M_PI, static_cast<int>(particles));

  mrpt::bayes::CParticleFilter pf;
  pf.m_options.PF_algorithm = mrpt::bayes::CParticleFilter::pfStandardProposal;
  pf.m_options.resamplingMethod = mrpt::bayes::CParticleFilter::prSystematic;
  pf.m_options.adaptiveSampleSize = false;
  pf.m_options.BETA = 0.5;
  pf.setMinLoggingLevel(mrpt::system::LVL_ERROR);

  mrpt::obs::CActionRobotMovement2D::TMotionModelOptions motion;  // MRPT's Gaussian model
  if (tuned) {
    // Matched to the run's encoder noise (1 % of travel, 0.2 rad/m) with small per-step floors:
    // MRPT's defaults (1 cm and 0.2 deg per increment) are meant for ~1 Hz odometry, not 100 Hz.
    motion.gaussianModel.a1 = 0.01;
    motion.gaussianModel.a2 = 0.0;
    motion.gaussianModel.a3 = 0.2;
    motion.gaussianModel.a4 = 0.01;
    motion.gaussianModel.minStdXY = 0.0005;
    motion.gaussianModel.minStdPHI = 0.0005;
  }
  mcl_bench::Score score;
  for (const auto& r : run.rows) {
    const auto t0 = std::chrono::steady_clock::now();
    mrpt::obs::CActionCollection actions;
    mrpt::obs::CActionRobotMovement2D move;
    move.computeFromOdometry(mrpt::poses::CPose2D(r.odo_dx, r.odo_dy, r.odo_dtheta), motion);
    actions.insert(move);
    mrpt::obs::CSensoryFrame sf;
    if (r.beacon_id >= 0) {
      auto obs = mrpt::obs::CObservationBeaconRanges::Create();
      obs->minSensorDistance = 0.0f;
      obs->maxSensorDistance = 10.0f;
      obs->stdError = static_cast<float>(range_std);
      mrpt::obs::CObservationBeaconRanges::TMeasurement m;
      m.sensedDistance = static_cast<float>(r.range);
      m.beaconID = r.beacon_id;
      obs->sensedData.push_back(m);
      sf.insert(obs);
    }
    pf.executeOn(pdf, &actions, &sf);
    mrpt::poses::CPose2D mean;
    pdf.getMean(mean);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    score.add(r, mean.x(), mean.y(), mean.phi(), ms);
  }
  score.print(mode, static_cast<std::size_t>(particles));
  return 0;
}
