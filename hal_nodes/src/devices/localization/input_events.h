// The localization device's input queue. Every input message is an event kept in order of
// its header stamp (not of arrival), and events are handed to the filter only once they are
// older than the newest odometry by ~latency: then every message of that period has arrived,
// so a bag replayed through the device gives the same sequence of filter steps, run after
// run, whatever the timing of the callbacks and of the refresh timer.
#pragma once

#include <algorithm>
#include <cstdint>
#include <deque>
#include <mutex>
#include <vector>

namespace hal_nodes::localization {

template <class Payload>
class InputEvents {
 public:
  struct Event {
    double stamp;
    int order;       // tie-break at equal stamps: lower first (secondary odometry pairs before the primary)
    uint64_t seq;    // arrival, last tie-break
    Payload payload;
  };

  explicit InputEvents(std::size_t capacity) : capacity_(capacity) {}

  // Returns false (and counts a drop) when the queue is full.
  bool push(double stamp, int order, Payload p) {
    std::lock_guard<std::mutex> lk(mutex_);
    if (events_.size() >= capacity_) {
      ++dropped_;
      return false;
    }
    events_.push_back({stamp, order, seq_++, std::move(p)});
    return true;
  }

  // The events stamped at or before `watermark`, in stamp order; they leave the queue.
  // Events older than what was already handed out arrive too late: they are dropped, counted.
  std::vector<Event> takeUntil(double watermark) {
    std::lock_guard<std::mutex> lk(mutex_);
    std::vector<Event> out;
    std::deque<Event> keep;
    for (auto& e : events_) {
      if (e.stamp < handed_) {
        ++late_;
      } else if (e.stamp <= watermark) {
        out.push_back(std::move(e));
      } else {
        keep.push_back(std::move(e));
      }
    }
    events_.swap(keep);
    std::stable_sort(out.begin(), out.end(), [](const Event& a, const Event& b) {
      if (a.stamp != b.stamp) return a.stamp < b.stamp;
      if (a.order != b.order) return a.order < b.order;
      return a.seq < b.seq;
    });
    if (!out.empty()) handed_ = std::max(handed_, out.back().stamp);
    return out;
  }

  void clear() {
    std::lock_guard<std::mutex> lk(mutex_);
    events_.clear();
  }
  unsigned long dropped() const { std::lock_guard<std::mutex> lk(mutex_); return dropped_; }
  unsigned long late() const { std::lock_guard<std::mutex> lk(mutex_); return late_; }
  std::size_t size() const { std::lock_guard<std::mutex> lk(mutex_); return events_.size(); }

 private:
  mutable std::mutex mutex_;
  std::deque<Event> events_;
  std::size_t capacity_;
  uint64_t seq_ = 0;
  double handed_ = -1e300;
  unsigned long dropped_ = 0, late_ = 0;
};

}  // namespace hal_nodes::localization
