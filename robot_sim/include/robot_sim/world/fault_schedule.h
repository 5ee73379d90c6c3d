// Faults scripted in simulated time: each entry starts at `start` and ends at `end` (never
// when end <= start). update(now) returns the transitions due, in time order, so the
// simulator applies them on its stepping thread at the exact step they fall in.
#pragma once

#include <mutex>
#include <string>
#include <vector>

namespace robot_sim {

struct FaultEntry {
  std::string kind;
  std::string target;
  double start = 0.0;
  double end = 0.0;        // <= start: until cleared
  double magnitude = 0.0;  // 0: the kind's default
  bool active = false;
  bool open() const { return end <= start; }
};

struct FaultTransition {
  FaultEntry fault;
  bool activate = true;
};

class FaultSchedule {
 public:
  // An entry added with active = true was applied by the caller; only its end is scheduled.
  void add(const FaultEntry& fault);
  // Ends every entry of kind/target: active ones at the next update, pending ones never start.
  // Returns whether any matched.
  bool clear(const std::string& kind, const std::string& target);
  std::vector<FaultTransition> update(double now);
  std::vector<FaultEntry> active() const;
  bool empty() const;

 private:
  mutable std::mutex mutex_;
  std::vector<FaultEntry> entries_;
  std::vector<FaultEntry> cleared_;  // active entries to switch off at the next update
};

}  // namespace robot_sim
