// The diagnostics summary: one line per device (/diagnostics status name), worst first.
#pragma once

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/time.h>

#include <map>
#include <string>
#include <vector>

namespace match_panel {

struct DeviceLine {
  std::string name;
  int level = 0;  // diagnostic_msgs::DiagnosticStatus OK, WARN, ERROR, STALE (3)
  std::string message;
  bool stale = false;  // no update for stale_after seconds: level is STALE
};

// "OK", "WARN", "ERROR", "STALE" (any other level: its number).
std::string levelName(int level);

class DiagnosticsSummary {
 public:
  explicit DiagnosticsSummary(double stale_after = 3.0) : stale_after_(stale_after) {}

  // A device's worst status in one array replaces what it said before (a device that got
  // better shows better): several statuses of one name in one array count by the worst.
  void update(const diagnostic_msgs::DiagnosticArray& array, const ros::Time& received);

  // Every device seen, worst first (STALE, ERROR, WARN, OK), then by name.
  std::vector<DeviceLine> lines(const ros::Time& now) const;

  void clear() { devices_.clear(); }

 private:
  struct Entry {
    int level;
    std::string message;
    ros::Time updated;
  };
  double stale_after_;
  std::map<std::string, Entry> devices_;
};

}  // namespace match_panel
