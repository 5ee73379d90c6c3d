#include "match_panel/match_clock.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace match_panel {

std::string formatClock(double seconds) {
  if (!(seconds > 0.0)) seconds = 0.0;  // also NaN
  // Whole tenths; the epsilon keeps 83.4 (stored as 83.39999...) from showing as 83.3.
  const long tenths = static_cast<long>(std::floor(seconds * 10.0 + 1e-6));
  char text[32];
  std::snprintf(text, sizeof(text), "%ld:%02ld.%ld", tenths / 600, (tenths / 10) % 60, tenths % 10);
  return text;
}

double countDown(double remaining, double age, bool running) {
  if (!running) return std::max(0.0, remaining);
  // A message from the future (clock skew) does not add time.
  return std::max(0.0, remaining - std::max(0.0, age));
}

}  // namespace match_panel
