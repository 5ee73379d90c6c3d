// The beacons device's equation from a receiver's raw time of flight to a distance:
//   distance = scale * c(T) * delta + offset + beacon_offsets[id]
//   c(T) = 331.3 m/s * sqrt(1 + T / 273.15 K)     (speed of sound in dry air, T in deg C)
// `scale` absorbs what the physics leaves out (humidity, the receiver's clock), `offset` the
// fixed delays (transmitter trigger, receiver threshold) and the beacon_offsets the
// geometry of each beacon. scale and offset can be fitted by least squares from distances
// measured some other way.
#pragma once

#include <string>
#include <vector>

namespace hal_nodes {

double speedOfSound(double temperature_celsius);

struct BeaconEquation {
  double temperature = 20.0;          // [deg C]
  double scale = 1.0;                 // > 0
  double offset = 0.0;                // [m]
  std::vector<double> beacon_offsets; // [m] per beacon id (missing ids: 0)

  double beaconOffset(int id) const;
  double distance(int beacon_id, double delta_s) const;
};

struct LineFit {
  bool ok = false;
  std::string why;      // when !ok
  double slope = 0.0;
  double intercept = 0.0;
  double rms = 0.0;     // residual
};

// Ordinary least squares y = slope * x + intercept; needs >= 2 points with distinct x.
LineFit fitLine(const std::vector<double>& x, const std::vector<double>& y);

// Fit scale and offset of `eq` (temperature and beacon offsets kept) to pairs of raw delta
// [s] and true distance [m]; ids may be empty or give each pair's beacon id.
LineFit fitEquation(BeaconEquation& eq, const std::vector<double>& delta_s, const std::vector<double>& distance,
                    const std::vector<int>& ids);

}  // namespace hal_nodes
