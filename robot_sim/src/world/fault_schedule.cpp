#include "robot_sim/world/fault_schedule.h"

#include <algorithm>

namespace robot_sim {

void FaultSchedule::add(const FaultEntry& fault) {
  std::lock_guard<std::mutex> lock(mutex_);
  entries_.push_back(fault);  // active already when the caller applied it itself
}

bool FaultSchedule::clear(const std::string& kind, const std::string& target) {
  std::lock_guard<std::mutex> lock(mutex_);
  bool any = false;
  for (auto it = entries_.begin(); it != entries_.end();) {
    if (it->kind == kind && it->target == target) {
      any = true;
      if (it->active) cleared_.push_back(*it);
      it = entries_.erase(it);
    } else {
      ++it;
    }
  }
  return any;
}

std::vector<FaultTransition> FaultSchedule::update(double now) {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<FaultTransition> out;
  for (auto& f : cleared_) out.push_back({f, false});
  cleared_.clear();
  // Ends before starts, so a fault re-scripted back to back ends and starts again cleanly.
  for (auto it = entries_.begin(); it != entries_.end();) {
    if (it->active && !it->open() && now >= it->end) {
      out.push_back({*it, false});
      it = entries_.erase(it);
    } else {
      ++it;
    }
  }
  for (auto& f : entries_) {
    if (!f.active && now >= f.start) {
      f.active = true;
      out.push_back({f, true});
    }
  }
  // A fault shorter than a step still happens: it starts now and ends at the next update.
  return out;
}

std::vector<FaultEntry> FaultSchedule::active() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<FaultEntry> out;
  for (const auto& f : entries_)
    if (f.active) out.push_back(f);
  return out;
}

bool FaultSchedule::empty() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return entries_.empty() && cleared_.empty();
}

}  // namespace robot_sim
