// Shared by the two localization bench tools (ours: mcl_bench, MRPT's stock MCL:
// mcl_bench_stock): reading a synthetic beacon run (scripts/bench/data/README.md) and scoring a
// run of estimates into the one-line format that README defines.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace mcl_bench {

struct Row {
  double t, odo_dx, odo_dy, odo_dtheta;
  int beacon_id;
  double range, true_x, true_y, true_theta;
};

struct Run {
  std::vector<std::pair<double, double>> beacons;
  double start_x = 0, start_y = 0, start_theta = 0;
  std::vector<Row> rows;
};

inline Run readRun(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open run file '" + path + "' (scripts/bench/mcl.sh writes the runs into build/bench_data)");
  Run run;
  std::string line;
  bool header_seen = false;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      std::istringstream ss(line.substr(1));
      std::string key;
      ss >> key;
      if (key == "beacon") {
        int id;
        double x, y;
        ss >> id >> x >> y;
        if (id < 0) throw std::runtime_error("bad beacon line: " + line);
        if (static_cast<std::size_t>(id) >= run.beacons.size()) run.beacons.resize(id + 1);
        run.beacons[id] = {x, y};
      } else if (key == "start") {
        ss >> run.start_x >> run.start_y >> run.start_theta;
      }
      continue;
    }
    if (!header_seen) {
      header_seen = true;
      if (line.rfind("t,", 0) == 0) continue;
    }
    Row r;
    if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%d,%lf,%lf,%lf,%lf", &r.t, &r.odo_dx, &r.odo_dy, &r.odo_dtheta,
                    &r.beacon_id, &r.range, &r.true_x, &r.true_y, &r.true_theta) != 9)
      throw std::runtime_error("bad row in " + path + ": " + line);
    run.rows.push_back(r);
  }
  if (run.beacons.empty() || run.rows.empty()) throw std::runtime_error(path + ": no beacons or no rows");
  return run;
}

inline double wrap(double a) { return std::remainder(a, 2.0 * M_PI); }

// Collects per-update cost and error; prints the README's line.
class Score {
 public:
  void add(const Row& r, double x, double y, double theta, double ms) {
    cost_.push_back(ms);
    t_.push_back(r.t);
    err_.push_back(std::hypot(x - r.true_x, y - r.true_y));
    herr_.push_back(wrap(theta - r.true_theta));
  }

  void print(const std::string& mode, std::size_t particles) const {
    std::vector<double> c = cost_;
    std::sort(c.begin(), c.end());
    auto pct = [&](double q) { return c.empty() ? 0.0 : c[std::min(c.size() - 1, static_cast<std::size_t>(q * c.size()))]; };
    double se = 0, mx = 0, sh = 0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < t_.size(); ++i) {
      if (t_[i] < 5.0) continue;
      se += err_[i] * err_[i];
      sh += herr_[i] * herr_[i];
      mx = std::max(mx, err_[i]);
      ++n;
    }
    const double rmse = n ? std::sqrt(se / n) : 0.0, hrmse = n ? std::sqrt(sh / n) : 0.0;
    std::printf("mode %s particles %zu updates %zu p50_ms %.3f p99_ms %.3f rmse_mm %.1f max_mm %.0f heading_rmse_deg %.2f converged_s %.2f\n",
                mode.c_str(), particles, cost_.size(), pct(0.5), pct(0.99), 1000.0 * rmse, 1000.0 * mx, hrmse * 180.0 / M_PI,
                converged());
  }

  // The first time the error stays under 50 mm for 1 s (-1: never).
  double converged() const {
    std::size_t start = 0;
    bool in = false;
    for (std::size_t i = 0; i < t_.size(); ++i) {
      if (err_[i] < 0.05) {
        if (!in) {
          in = true;
          start = i;
        }
        if (t_[i] - t_[start] >= 1.0) return t_[start];
      } else {
        in = false;
      }
    }
    return -1.0;
  }

 private:
  std::vector<double> cost_, t_, err_, herr_;
};

}  // namespace mcl_bench
