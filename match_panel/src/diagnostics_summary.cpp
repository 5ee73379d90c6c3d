#include "match_panel/diagnostics_summary.h"

#include <diagnostic_msgs/DiagnosticStatus.h>

#include <algorithm>
#include <cstdio>

namespace match_panel {

using diagnostic_msgs::DiagnosticStatus;

std::string levelName(int level) {
  switch (level) {
    case DiagnosticStatus::OK: return "OK";
    case DiagnosticStatus::WARN: return "WARN";
    case DiagnosticStatus::ERROR: return "ERROR";
    case DiagnosticStatus::STALE: return "STALE";
    default: return std::to_string(level);
  }
}

void DiagnosticsSummary::update(const diagnostic_msgs::DiagnosticArray& array, const ros::Time& received) {
  std::map<std::string, Entry> worst;  // this array's worst per name
  for (const auto& status : array.status) {
    auto it = worst.find(status.name);
    if (it == worst.end() || status.level > it->second.level)
      worst[status.name] = Entry{status.level, status.message, received};
  }
  for (auto& kv : worst) devices_[kv.first] = kv.second;
}

std::vector<DeviceLine> DiagnosticsSummary::lines(const ros::Time& now) const {
  std::vector<DeviceLine> result;
  for (const auto& kv : devices_) {
    DeviceLine line;
    line.name = kv.first;
    line.level = kv.second.level;
    line.message = kv.second.message;
    // Receipt time, not the header stamp: publishers stamp on their own clocks.
    const double silent = (now - kv.second.updated).toSec();
    if (silent > stale_after_) {
      // No fresh report: the last message is old news, not the state ("STALE: ok" misleads).
      line.stale = true;
      line.level = DiagnosticStatus::STALE;
      char buf[64];
      std::snprintf(buf, sizeof buf, "no report for %.0f s", silent);
      line.message = std::string(buf) + (kv.second.message.empty() ? "" : " (last said: " + kv.second.message + ")");
    }
    result.push_back(line);
  }
  std::stable_sort(result.begin(), result.end(), [](const DeviceLine& a, const DeviceLine& b) {
    return a.level > b.level;  // map order keeps the names sorted within a level
  });
  return result;
}

}  // namespace match_panel
