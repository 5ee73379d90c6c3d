// A transient fault a diagnostic check holds at its level for a while: a counter that only grows
// (bus-offs recovered from, board resets, malformed frames, bad serial bytes) is over the moment
// it grows, so a check that only said "it grew since my last look" would show it for one check
// of the many per published report (robot_core/diagnostic_reporter.h) and a team would miss it.
// An episode runs while the counter keeps growing and is shown until `hold` after the last
// check that saw it grow; its count runs from the start of the episode, not since a report.
// A clock that goes back (a simulation restarted) ends the episode. Checks are the only users,
// one at a time: no locking.
#pragma once

#include <ros/time.h>

namespace robot_core {

class HeldEpisode {
 public:
  explicit HeldEpisode(double hold_s = 1.0) : hold_(hold_s) {}

  // The counter as a check sees it now. True when this check began a new episode (a caller
  // that shows a breakdown of the counter takes its snapshot then).
  bool see(unsigned long count, const ros::Time& now) {
    bool began = false;
    if (count > seen_) {
      began = !shown(now);
      if (began) episode_start_ = seen_;
      until_ = now + hold_;
    }
    seen_ = count;
    return began;
  }

  // The counter taken as it is, not as an episode: a first check's (a power-on's, a bus's past).
  void take(unsigned long count) { seen_ = count; }

  bool shown(const ros::Time& now) const { return now < until_ && now + hold_ >= until_; }

  // How many the episode has counted so far.
  unsigned long count() const { return seen_ - episode_start_; }

 private:
  ros::Duration hold_;
  unsigned long seen_ = 0;           // the counter at the previous check
  unsigned long episode_start_ = 0;  // the counter when the episode began
  ros::Time until_;                  // shown until then
};

}  // namespace robot_core
