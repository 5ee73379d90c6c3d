// The beacon receiver on RS-232 (message format: boards/beacon_protocol.h).
//
// The receiver talks on its own; a reader thread blocks in poll() on the port so every
// message is stamped and published the moment its last byte arrives (the loop's service()
// would add up to one period of latency). service() only supervises: reopens a port that
// vanished and reports the board as answering while valid messages keep coming.
//
// Parameters (besides rate/loop): read and described in configure() (the table:
// hcl_drivers/PARAMETERS.md, make docs). Each beacon is heard every ~0.3 s at most on the
// table, hence the ~beacon_timeout default (0.6 s).
// /diagnostics: ERROR while a beacon is silent, and for 1 s after bad bytes on the line (garbage,
// checksum errors, truncated messages): noise on the serial line is named, not just counted.
// Topics: ~delta (hcl_drivers/BeaconDelta, every message, stamp = receive time of its last byte),
//         ~state (hcl_drivers/BeaconReceiverState, latched, newest delta per beacon + counters).
#include <hcl_drivers/BeaconDelta.h>
#include <hcl_drivers/BeaconReceiverState.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <thread>

#include <robot_core/held_episode.h>
#include <robot_core/priority_inheritance_mutex.h>

#include "hcl_drivers/board_nodelet.h"
#include "hcl_drivers/boards/beacon_protocol.h"
#include "hcl_drivers/transport/serial_port.h"
#include <robot_core/realtime.h>

namespace hcl_drivers {

using robot_core::ParameterError;

class BeaconReceiver : public Board {
 public:
  ~BeaconReceiver() override {
    running_ = false;
    if (reader_.joinable()) reader_.join();
  }

  void configure(const robot_core::Params& p) override {
    p.describe("port", "serial device path: /dev/ttyS0, /dev/ttyUSB0, or the emulator's pty link");
    port_path_ = p.requireString("port");
    p.describe("baud", "[bit/s] serial speed, a standard rate 1200..921600");
    baud_ = p.optionalInt("baud", 9600);
    if (transport::SerialPort::baudConstant(baud_) == 0)
      throw ParameterError("parameter " + p.qualified("baud") + " = " + std::to_string(baud_) +
                           ": allowed values: " + transport::SerialPort::allowedBauds());
    p.describe("beacons", "number of beacon ids reported in ~state; messages for other ids are counted and dropped");
    beacons_ = p.optionalInt("beacons", 3);
    p.requireInRange("beacons", beacons_, 1, 10);
    p.describe("silence_timeout", "[s] no valid message for this long = not answering");
    silence_timeout_ = p.optionalDouble("silence_timeout", 1.0);
    p.requirePositive("silence_timeout", silence_timeout_);
    p.describe("beacon_timeout", "[s] one beacon unheard this long while others are heard: ERROR naming it");
    beacon_timeout_ = p.optionalDouble("beacon_timeout", 0.6);
    p.requirePositive("beacon_timeout", beacon_timeout_);
    p.describe("check_window", "[s] how long the hardware doctor listens to the port");
    check_window_ = p.optionalDouble("check_window", 2.0);  // the doctor's
  }

  void init(BoardContext& ctx) override {
    state_.delta_us.assign(beacons_, 0);
    state_.stamps.assign(beacons_, ros::Time());
    port_ = std::make_unique<transport::SerialPort>(port_path_, baud_);
    delta_pub_ = ctx.pnh.advertise<BeaconDelta>("delta", 100);
    state_pub_ = ctx.pnh.advertise<BeaconReceiverState>("state", 1, true);
    running_ = true;
    reader_ = std::thread([this] { readLoop(); });
  }

  // The doctor: open the port at the configured speed, listen ~check_window seconds,
  // parse what comes: frames, their rate, the beacons heard and the parse errors.
  void check(BoardContext& /*ctx*/, CheckReport& report) override {
    const std::string& port = port_path_;
    const int baud = baud_;
    const int beacons = beacons_;
    const double window = check_window_;
    transport::SerialPort serial(port, baud);
    std::string error;
    const std::string expected_port = port + " at " + std::to_string(baud) + " baud";
    if (!serial.open(error)) {
      report.fail("port", expected_port, error,
                  "is the receiver plugged in (ls -l " + port + ")? make install-robot gives its USB adapter this name");
      return;
    }
    report.ok("port", expected_port, "open");
    beacon_protocol::Parser parser;
    std::vector<beacon_protocol::Message> messages;
    std::vector<bool> heard(10, false);
    unsigned long bytes = 0;
    uint8_t buf[256];
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(window);
    while (std::chrono::steady_clock::now() < until) {
      const long n = serial.read(buf, sizeof buf, 0.1, error);
      if (n < 0) break;
      bytes += static_cast<unsigned long>(n);
      parser.feed(buf, static_cast<std::size_t>(n), messages);
    }
    for (const auto& m : messages) heard[m.beacon_id] = true;
    const auto& st = parser.stats();
    const unsigned long bad = st.checksum_errors + st.malformed;
    char found[160];
    std::snprintf(found, sizeof found, "%.1f frames/s, %lu parse errors (%.0f %%), %lu garbage bytes in %.1f s",
                  messages.size() / window, bad, 100.0 * bad / std::max(1ul, bad + st.messages), st.garbage_bytes, window);
    const std::string expected_frames = "$B frames from " + std::to_string(beacons) + " beacons";
    if (messages.empty())
      report.fail("frames", expected_frames, bytes ? std::string(found) : "no bytes in " + std::to_string(window).substr(0, 3) + " s" +
                      (error.empty() ? "" : " (" + error + ")"),
                  bytes ? "bytes but no valid frame: is the baud rate (" + std::to_string(baud) + ") the receiver's?"
                        : "the receiver is silent: its power, its TX wire, the beacons' sync radio");
    else if (bad || st.garbage_bytes)
      report.warn("frames", expected_frames, found, "noise on the line: check the cable, its shield and the ground");
    else
      report.ok("frames", expected_frames, found);
    std::string missing;
    for (int id = 0; id < beacons; ++id)
      if (!heard[id]) missing += (missing.empty() ? "" : ", ") + std::to_string(id);
    if (!messages.empty() && !missing.empty())
      report.warn("beacons", "beacons 0.." + std::to_string(beacons - 1) + " heard", "not heard: " + missing,
                  "a beacon is off, or masked from the receiver where the robot stands");
  }

  bool service() override {
    std::lock_guard lk(mutex_);
    if (!open_) {
      fail(port_error_.empty() ? "port not open yet" : port_error_);
      return false;
    }
    if (last_valid_.isZero() || (ros::Time::now() - last_valid_).toSec() > silence_timeout_) {
      fail("no valid message for " + std::to_string(silence_timeout_) + " s on " + port_->path());
      return false;
    }
    return true;
  }

  void halt() override {}  // a receiver: nothing to make safe

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    std::lock_guard lk(mutex_);
    stat.add("port", port_->path());
    stat.add("port open", open_ ? "yes" : "no");
    stat.add("reopens", reopens_);
    stat.add("valid messages", stats_.messages);
    stat.add("garbage bytes", stats_.garbage_bytes);
    stat.add("checksum errors", stats_.checksum_errors);
    stat.add("malformed messages", stats_.malformed);
    stat.add("unknown beacon ids", unknown_ids_);
    // Bad bytes are over at once (the parser resynchronised): named at ERROR for a second after
    // the last of them, counted over the episode (robot_core/held_episode.h), then OK again.
    const ros::Time now = ros::Time::now();
    if (bad_input_.see(stats_.garbage_bytes + stats_.checksum_errors + stats_.malformed, now))
      episode_start_ = seen_;  // a new episode: its breakdown counts from the check before it
    if (bad_input_.shown(now))
      stat.mergeSummaryf(diagnostic_msgs::DiagnosticStatus::ERROR,
                         "bad input on %s: %lu garbage byte(s), %lu checksum error(s), %lu malformed message(s)",
                         port_->path().c_str(), stats_.garbage_bytes - episode_start_.garbage_bytes,
                         stats_.checksum_errors - episode_start_.checksum_errors,
                         stats_.malformed - episode_start_.malformed);
    seen_ = stats_;
    // One beacon silent while the receiver hears the others (all silent: the board itself is).
    if (!last_valid_.isZero() && (now - last_valid_).toSec() <= silence_timeout_) {
      std::string silent;
      for (std::size_t id = 0; id < state_.stamps.size(); ++id) {
        const double age = state_.stamps[id].isZero() ? -1.0 : (now - state_.stamps[id]).toSec();
        if (age <= beacon_timeout_) continue;
        char one[48];
        snprintf(one, sizeof one, "%s%zu for %.2f s", silent.empty() ? "" : ", ", id, age);
        silent += one;
      }
      if (!silent.empty())
        stat.mergeSummaryf(diagnostic_msgs::DiagnosticStatus::ERROR,
                           "beacon(s) silent while the others are heard: %s (hidden, or battery)", silent.c_str());
    }
  }

 private:
  void readLoop() {
    robot_core::enterRealtime("the beacon line reader");
    beacon_protocol::Parser parser;
    std::vector<beacon_protocol::Message> msgs;
    uint8_t buf[256];
    bool was_open = false;
    while (running_) {
      std::string err;
      if (!port_->isOpen()) {
        if (!port_->open(err)) {
          setPort(false, err);
          std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the device may come back
          continue;
        }
        if (was_open) {
          std::lock_guard lk(mutex_);
          ++reopens_;
        }
        was_open = true;
        parser = beacon_protocol::Parser();  // half a message from before is garbage now
        setPort(true, "");
      }
      const long n = port_->read(buf, sizeof(buf), 0.1, err);
      if (n < 0) {
        setPort(false, err);
        continue;
      }
      if (n == 0) continue;
      const ros::Time stamp = ros::Time::now();  // the chunk's last byte just arrived
      msgs.clear();
      const auto before = parser.stats();
      parser.feed(buf, static_cast<std::size_t>(n), msgs);
      publish(msgs, stamp, parser.stats(), before);
    }
  }

  void setPort(bool open, const std::string& err) {
    std::lock_guard lk(mutex_);
    open_ = open;
    if (!err.empty()) port_error_ = err;
  }

  void publish(const std::vector<beacon_protocol::Message>& msgs, const ros::Time& stamp,
               const beacon_protocol::Stats& now, const beacon_protocol::Stats& before) {
    std::lock_guard lk(mutex_);
    // Parser stats restart with the parser at each reopen: accumulate the increments.
    stats_.messages += now.messages - before.messages;
    stats_.garbage_bytes += now.garbage_bytes - before.garbage_bytes;
    stats_.checksum_errors += now.checksum_errors - before.checksum_errors;
    stats_.malformed += now.malformed - before.malformed;
    bool changed = now.garbage_bytes != before.garbage_bytes || now.malformed != before.malformed ||
                   now.checksum_errors != before.checksum_errors;
    for (const auto& m : msgs) {
      if (m.beacon_id >= state_.delta_us.size()) {
        ++unknown_ids_;
        continue;
      }
      BeaconDelta::Ptr d(new BeaconDelta);
      d->header.stamp = stamp;
      d->beacon_id = m.beacon_id;
      d->delta_us = m.delta_us;
      delta_pub_.publish(d);
      state_.delta_us[m.beacon_id] = m.delta_us;
      state_.stamps[m.beacon_id] = stamp;
      state_.last_beacon_id = m.beacon_id;
      state_.header.stamp = stamp;
      last_valid_ = stamp;
      changed = true;
    }
    if (!changed) return;
    state_.messages = stats_.messages;
    state_.garbage_bytes = stats_.garbage_bytes;
    state_.checksum_errors = stats_.checksum_errors;
    state_.malformed = stats_.malformed;
    state_.port_open = open_;
    state_pub_.publish(state_);
  }

  std::string port_path_;  // the parameters configure() read
  int baud_ = 9600, beacons_ = 3;
  double check_window_ = 2.0;
  std::unique_ptr<transport::SerialPort> port_;  // used by the reader thread only
  double silence_timeout_ = 1.0;
  double beacon_timeout_ = 0.6;
  // Bad input (garbage + checksum + malformed) as diagnose() holds it at ERROR, and its breakdown
  // at the previous check and at the start of the episode.
  robot_core::HeldEpisode bad_input_;
  beacon_protocol::Stats seen_, episode_start_;
  ros::Publisher delta_pub_, state_pub_;
  std::atomic<bool> running_{false};
  std::thread reader_;

  robot_core::PriorityInheritanceMutex mutex_;  // reader thread vs loop vs diagnostics' checks
  bool open_ = false;
  std::string port_error_;
  ros::Time last_valid_;
  beacon_protocol::Stats stats_;
  unsigned long unknown_ids_ = 0, reopens_ = 0;
  BeaconReceiverState state_;
};

}  // namespace hcl_drivers

HCL_EXPORT_BOARD(BeaconReceiver,
                 "Beacon receiver on RS-232 (termios): beacon id + time-of-flight delta per message.")
