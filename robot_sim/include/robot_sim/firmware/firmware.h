// A Firmware is the emulator of one board's firmware: it owns the board's end of the
// channel (a UDP port, a CAN bus, a pty, an i2c socket) and answers with the same bytes the
// real board would, reading and driving the simulated world when there is one.
//
// Emulators are independent implementations of the board side, written from the board's
// protocol documentation, never by calling the driver's encoder: a shared bug would hide.
#pragma once

#include <robot_core/params.h>
#include <ros/ros.h>

#include <algorithm>
#include <atomic>
#include <string>

namespace robot_sim {

class World;  // the simulated world (robot_sim/world), absent for world-less emulators

// The board's own clock [s]: ROS time, so in a simulation the simulator's /clock (a heartbeat
// period, a watchdog or a frame period is the same in simulated seconds at any real-time
// factor, as the drivers measure them), and the wall clock where emulators run alone.
inline double firmwareNow() { return ros::Time::now().toSec(); }

// How long [s, wall] a firmware loop may block before it looks at its clock again when its next
// event is `left` seconds away on that clock: a simulated clock may run faster than the wall.
inline double firmwareWallSlice(double left, double slice = 0.005) {
  return left <= 0.0 ? 0.0 : (ros::Time::isSimTime() ? std::min(left, slice) : left);
}

struct FirmwareContext {
  ros::NodeHandle nh;   // global namespace: publish truth under /sim/...
  ros::NodeHandle pnh;  // the emulator's own namespace (a world-less emulator's live overrides)
  robot_core::Params params;  // its parameters (configure() has read them before start())
  std::string name;     // e.g. "ExampleBoard": the board type name of its driver
  World* world = nullptr;
};

class Firmware {
 public:
  virtual ~Firmware() = default;

  // Read every parameter into members and nothing else: no channel, no world, no ROS. Called
  // before start(), and alone by check_sim_config (check_config) over a config file with no
  // master, so a wrong value is found in seconds and the parameter tables (make docs) come from
  // these reads (Params::describe beside each). Throw robot_core::ParameterError on a bad value.
  virtual void configure(const robot_core::Params& params) { (void)params; }
  // Check the configured names against the world (when there is one), open the channel and start
  // answering. Throw std::runtime_error on what only the running simulation can refuse.
  virtual void start(FirmwareContext& ctx) = 0;
  // Stop answering and close the channel.
  virtual void stop() = 0;

  // Requests from the board's driver answered so far (CAN RTRs, I2C reads): the robot's work
  // rate, which "as fast as the machine goes" watches (machine_pace.h) to never outrun it.
  unsigned long polls() const { return polls_; }

  // Fault injection: a silent board keeps running but never answers.
  void setSilent(bool silent) { silent_ = silent; }
  bool silent() const { return silent_; }

  // Fault injection hook called by the simulator's /sim/inject_fault (on the simulator's
  // thread): kind is "board_silent", "can_bus_off", "serial_garbage", "serial_truncate" or an
  // emulator-specific kind. Return false when this emulator does not emulate that fault.
  // Override to add kinds; call Firmware::applyFault for the ones you do not handle.
  virtual bool applyFault(const std::string& kind, bool active) {
    if (kind != "board_silent") return false;
    setSilent(active);
    return true;
  }

 protected:
  void countPoll() { ++polls_; }

 private:
  std::atomic<bool> silent_{false};
  std::atomic<unsigned long> polls_{0};
};

}  // namespace robot_sim
