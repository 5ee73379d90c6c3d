// The Autopilot's control curves: a command as a function of an error, defined by two
// parameters so each robot tunes its own feel in config:
//
//   fraction(e) = sign(e) * min(1, (|e| / saturation) ^ exponent)
//
// * saturation: the error at and beyond which the full command is given (the speed curve's
//   "slow down from here" distance [m], the turn curve's "full turn from here" angle [rad]);
// * exponent: the shape below it: 1 is proportional, < 1 keeps more command close to the goal
//   (0.5 is the constant-deceleration profile, fast but needs stiff motors), > 1 creeps in
//   softly.
// The speed curve maps distance-to-goal to a fraction of the speed limit; the turn curve maps
// angular deviation to a fraction of the turn-rate limit, i.e. of the wheel-speed difference
// (wheel difference = turn rate * track width). Both reach zero exactly at zero error, so the
// robot slows down as it arrives instead of oscillating around the goal.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

namespace hal_nodes {
namespace driver {

struct ControlCurve {
  double saturation = 1.0;  // error at which the command saturates, > 0
  double exponent = 1.0;    // shape, in [0.2, 4]

  // Command fraction in [-1, 1] with the sign of the error.
  double fraction(double error) const {
    const double e = std::fabs(error);
    if (!(e > 0.0)) return 0.0;  // also NaN
    const double f = e >= saturation ? 1.0 : std::pow(e / saturation, exponent);
    return error > 0.0 ? f : -f;
  }

  // Empty when usable, else why not (for the parameter error message).
  std::string invalidReason() const {
    if (!(saturation > 0.0) || !std::isfinite(saturation)) return "saturation must be > 0";
    if (!(exponent >= 0.2 && exponent <= 4.0)) return "exponent must be in [0.2, 4]";
    return "";
  }
};

// The speed a brake of constant deceleration `decel` can still stop from within `remaining`:
// capping a curve with it makes any curve feasible under the acceleration limit.
inline double brakingSpeed(double remaining, double decel) { return std::sqrt(2.0 * decel * std::max(0.0, remaining)); }

}  // namespace driver
}  // namespace hal_nodes
