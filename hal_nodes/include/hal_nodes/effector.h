// An Effector is a Device that moves something. Besides init/refresh/halt it must be able to
// deactivate(): stop acting at once and refuse commands until reactivated. Every effector
// follows the latched /effectors/deactivated topic (see effector_supervisor.h), so one call to
// the /effectors/deactivate service freezes them all: end of match, emergency.
#pragma once

#include <atomic>

#include "hal_nodes/device.h"

namespace hal_nodes {

class Effector : public Device {
 public:
  // Stop acting now (e.g. command zero speed, servos off). Called on the callback queue.
  virtual void deactivate() = 0;
  // Called when the deactivation is lifted. Default: nothing to do.
  virtual void reactivate() {}

  // While deactivated, refresh() must not command anything.
  bool active() const { return active_; }

  // Framework side.
  void setActive(bool active) {
    const bool was = active_.exchange(active);
    if (was && !active) deactivate();
    if (!was && active) reactivate();
  }

 private:
  std::atomic<bool> active_{true};
};

}  // namespace hal_nodes
