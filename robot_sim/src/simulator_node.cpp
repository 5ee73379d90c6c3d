// The simulator: steps the world at a fixed dt in its own thread, paced against the wall clock
// at ~real_time_factor, publishes /clock, ground truth (/sim/*), rviz markers, and hosts the
// firmware emulators of every board (~firmware) on top of the world.
//
// Parameters (private, /sim/...): its own (SimulatorSettings), ~world (the world, config.h) and
// ~firmware (the emulators); the tables in robot_sim/PARAMETERS.md (make docs).
// Names below are relative to the node's namespace (/ in the robot launch files), so several
// simulators can run side by side in a test under different namespaces.
// Topics: /clock, /sim/ground_truth + /sim/opponent (nav_msgs/Odometry), /sim/elements
//   (robot_sim/GameElements), /sim/match (robot_sim/MatchState), /sim/score (std_msgs/Int32: our
//   points), /sim/score_events (robot_sim/ScoreEvents, latched), /sim/faults
//   (robot_sim/ActiveFaults, latched), /sim/markers (visualization_msgs/MarkerArray);
//   in: /sim/debug/motor_command (robot_sim/DebugMotorCommand, sim-only test input),
//   brain/match_status (smart_brain/MatchStatus): a brain started without the cord (its ~start
//   service) pulls the simulated cord, so the referee's match starts with the brain's.
// Services: /sim/inject_fault, /sim/teleport, /sim/place_opponent, /sim/set_switch, /sim/pause
//   (std_srvs/SetBool), /sim/set_real_time_factor (robot_sim/SetRealTimeFactor: a new pace for the
//   running simulation, e.g. real time for a test's wall-clock case in a test run as fast as the
//   machine goes).
#include <robot_sim/ActiveFaults.h>
#include <robot_sim/DebugMotorCommand.h>
#include <robot_sim/InjectFault.h>
#include <robot_sim/PlaceOpponent.h>
#include <robot_sim/SetRealTimeFactor.h>
#include <robot_sim/SetSwitch.h>
#include <robot_sim/Teleport.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <smart_brain/MatchStatus.h>
#include <std_msgs/Int32.h>
#include <std_srvs/SetBool.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <memory>
#include <thread>

#include <robot_core/realtime.h>

#include "machine_pace.h"
#include "robot_sim/firmware/firmware_host.h"
#include "robot_sim/world/fault_schedule.h"
#include "robot_sim/world/ros_world_io.h"
#include "robot_sim/world/sim_world.h"
#include "robot_sim/world/simulator_settings.h"

namespace robot_sim {

namespace {
// A rate in simulated time: due() once per period, on the step grid.
struct SimRate {
  double period = 0.0;
  double next = 0.0;
  bool due(double t) {
    if (period <= 0.0 || t + 1e-9 < next) return false;
    next = std::max(next + period, t);
    return true;
  }
};
}  // namespace

class Simulator {
 public:
  Simulator(ros::NodeHandle nh, ros::NodeHandle pnh) : nh_(nh), pnh_(pnh) {}

  ~Simulator() {
    running_ = false;
    if (thread_.joinable()) thread_.join();
    if (host_) host_->stopAll();
  }

  // Reads the parameters and starts everything; false (after one FATAL line) on a bad one.
  bool start() {
    try {
      readParameters();
      config_ = loadWorldConfig(nh_, pnh_);
      config_.seed = static_cast<unsigned>(settings_.seed);
      world_ = std::make_unique<SimWorld>(config_, config_.seed);
    } catch (const std::exception& e) {
      ROS_FATAL("%s", e.what());
      return false;
    }
    clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("clock", 10);
    truth_pub_ = nh_.advertise<nav_msgs::Odometry>("sim/ground_truth", 50);
    opponent_pub_ = nh_.advertise<nav_msgs::Odometry>("sim/opponent", 50);
    elements_pub_ = nh_.advertise<GameElements>("sim/elements", 5);
    match_pub_ = nh_.advertise<robot_sim::MatchState>("sim/match", 5);
    score_pub_ = nh_.advertise<std_msgs::Int32>("sim/score", 5);  // our points, the plain figure
    score_events_pub_ = nh_.advertise<ScoreEvents>("sim/score_events", 1, true);
    score_events_pub_.publish(ScoreEvents());
    faults_pub_ = nh_.advertise<ActiveFaults>("sim/faults", 5, true);
    markers_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("sim/markers", 2);
    motor_sub_ = nh_.subscribe("sim/debug/motor_command", 100, &Simulator::onMotorCommand, this);
    brain_sub_ = nh_.subscribe("brain/match_status", 1, &Simulator::onBrainStatus, this);
    services_.push_back(nh_.advertiseService("sim/inject_fault", &Simulator::onInjectFault, this));
    services_.push_back(nh_.advertiseService("sim/teleport", &Simulator::onTeleport, this));
    services_.push_back(nh_.advertiseService("sim/place_opponent", &Simulator::onPlaceOpponent, this));
    services_.push_back(nh_.advertiseService("sim/set_switch", &Simulator::onSetSwitch, this));
    services_.push_back(nh_.advertiseService("sim/pause", &Simulator::onPause, this));
    services_.push_back(nh_.advertiseService("sim/set_real_time_factor", &Simulator::onSetRealTimeFactor, this));
    publishClock(0.0);
    publishFaults();

    // The emulators start after the world exists; none configured is fine (world-only tests).
    XmlRpc::XmlRpcValue fw;
    if (settings_.firmware_enabled && pnh_.getParam("firmware", fw) && fw.getType() == XmlRpc::XmlRpcValue::TypeStruct && fw.size() > 0) {
      host_ = std::make_unique<FirmwareHost>(nh_, ros::NodeHandle(pnh_, "firmware"), world_.get());
      if (!host_->startFromParameters()) return false;
    } else {
      ROS_INFO("simulator: no firmware emulators %s under %s", settings_.firmware_enabled ? "configured" : "(disabled)",
               pnh_.resolveName("firmware").c_str());
    }
    try {
      readScriptedFaults();  // after the emulators: board targets must be running
    } catch (const std::exception& e) {
      ROS_FATAL("%s", e.what());
      return false;
    }
    running_ = true;
    thread_ = std::thread([this] { run(); });
    ROS_INFO("simulator: seed %d, real-time factor %g%s, dt %g s, %zu game elements", settings_.seed, rtf_.load(),
             paused_ ? " (paused)" : "", config_.dt, config_.table.elements.size());
    return true;
  }

 private:
  void readParameters() {
    settings_ = SimulatorSettings::read(robot_core::Params::of(pnh_));
    rtf_ = settings_.real_time_factor;
    paused_ = settings_.paused;
    truth_rate_.period = 1.0 / settings_.truth_rate;
    elements_rate_.period = 1.0 / settings_.elements_rate;
    match_rate_.period = 1.0 / settings_.match_rate;
    marker_rate_.period = 1.0 / settings_.marker_rate;
    // The emulators (simulated boards) and the simulated bus under them answer like hardware:
    // in real-time threads at this priority (robot_core/realtime.h). The world's stepping thread
    // stays at normal priority: as fast as the machine goes, it would starve everything else.
    robot_core::setRealtimePriority(settings_.realtime_priority);
  }

  // The scripted faults' kinds and targets, once the world and the emulators exist.
  void readScriptedFaults() {
    const std::string ns = pnh_.resolveName("faults");
    for (std::size_t i = 0; i < settings_.faults.size(); ++i) {
      std::string why;
      if (!validFault(settings_.faults[i], /*check_boards=*/true, &why))
        throw ConfigError("parameter " + ns + "[" + std::to_string(i) + "]: " + why);
      faults_.add(settings_.faults[i]);
    }
  }

  // Whether a fault request can be applied (kind known, target existing).
  bool validFault(const FaultEntry& f, bool check_boards, std::string* why) const {
    if (SimWorld::isWorldFault(f.kind)) {
      if (f.kind == "beacon_silent") {
        const int n = static_cast<int>(config_.table.beacons.size());
        for (int i = 0; i < n; ++i)
          if (f.target == std::to_string(i)) return true;
        *why = "beacon_silent: target must be a beacon id 0.." + std::to_string(n - 1);
        return false;
      }
      if (f.kind == "wheel_slip") {
        auto it = config_.robot.motors.find(f.target);
        if (it != config_.robot.motors.end() && !it->second.drive.empty()) return true;
        *why = "wheel_slip: target must be a drive motor under sim/world/robot/motors";
        return false;
      }
      if (!config_.opponent.enabled) {
        *why = "opponent_blocks: the opponent is disabled";
        return false;
      }
      return true;
    }
    // Any other kind is a board fault: the target emulator decides whether it emulates it.
    if (f.kind.empty() || f.target.empty()) {
      *why = "kind '" + f.kind +
             "' is not a world fault (beacon_silent, wheel_slip, opponent_blocks); a board fault (board_silent, "
             "can_bus_off, serial_garbage, serial_truncate or the emulator's own kinds) needs target: an emulator name";
      return false;
    }
    if (check_boards && (!host_ || !host_->find(f.target))) {
      std::string names;
      if (host_)
        for (const auto& kv : host_->all()) names += (names.empty() ? "" : ", ") + kv.first;
      *why = f.kind + ": target '" + f.target + "' is not a running emulator (running: " +
             (names.empty() ? "none" : names) + ")";
      return false;
    }
    return true;
  }

  // Switches a fault on or off; false + why when the target does not emulate it.
  bool applyFault(const FaultEntry& f, bool active, std::string* why) {
    if (SimWorld::isWorldFault(f.kind)) return world_->applyFault(f.kind, f.target, active, f.magnitude, why);
    Firmware* fw = host_ ? host_->find(f.target) : nullptr;
    if (!fw) {
      *why = "no emulator named '" + f.target + "'";
      return false;
    }
    if (!fw->applyFault(f.kind, active)) {
      *why = "emulator '" + f.target + "' does not emulate " + f.kind;
      return false;
    }
    return true;
  }

  // ------------------------------------------------------------ the stepping thread
  void run() {
    using Clock = std::chrono::steady_clock;
    auto anchor_wall = Clock::now();
    double anchor_sim = world_->time();
    auto last_clock = Clock::now() - std::chrono::hours(1);
    auto last_report = Clock::now();
    double report_sim = anchor_sim;
    std::size_t last_unknown = 0;
    auto last_names_check = Clock::now();
    const auto clock_gap = std::chrono::duration<double>(1.0 / settings_.clock_max_rate);
    MachinePace machine;
    RobotKeepingUp keeping_up;
    double rtf = rtf_;  // the requested factor this loop paces at (the service may change rtf_)
    double pace = rtf > 0.0 ? rtf : machine.factor();
    auto last_pace = Clock::now();
    while (running_ && ros::ok()) {
      if (rtf_ != rtf) {  // a new pace counts from here: simulated time goes on where it is
        rtf = rtf_;
        pace = rtf > 0.0 ? rtf : machine.factor();
        anchor_wall = Clock::now();
        anchor_sim = world_->time();
        report_sim = anchor_sim;
        last_report = anchor_wall;
      }
      if (paused_) {
        publishClock(world_->time());
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        anchor_wall = Clock::now();
        anchor_sim = world_->time();
        continue;
      }
      world_->step();
      const double t = world_->time();
      bool faults_changed = false;
      for (const FaultTransition& tr : faults_.update(t)) {
        std::string why;
        if (!applyFault(tr.fault, tr.activate, &why))
          ROS_ERROR("simulator: scripted fault %s/%s at t=%.3f: %s", tr.fault.kind.c_str(), tr.fault.target.c_str(),
                    t, why.c_str());
        else
          ROS_INFO("simulator: fault %s/%s %s at t=%.3f", tr.fault.kind.c_str(), tr.fault.target.c_str(),
                   tr.activate ? "on" : "off", t);
        faults_changed = true;
      }
      if (faults_changed) publishFaults();
      publishTruth(t);

      const auto now = Clock::now();
      if (now - last_clock >= clock_gap) {
        publishClock(t);
        last_clock = now;
      }
      if (now - last_names_check > std::chrono::seconds(1)) {
        // An emulator asking for a motor/sensor the robot lacks is a config mismatch: say so.
        const auto unknown = world_->unknownNames();
        if (unknown.size() > last_unknown) {  // once per new name, not per read
          std::string names;
          for (const auto& n : unknown) names += (names.empty() ? "" : ", ") + n;
          ROS_ERROR("simulator: emulators use names this robot does not have (sim/world/robot): %s", names.c_str());
          last_unknown = unknown.size();
        }
        last_names_check = now;
      }
      if (now - last_report > std::chrono::seconds(10)) {
        const double achieved = (t - report_sim) / std::chrono::duration<double>(now - last_report).count();
        if (rtf > 0.0 && achieved < 0.9 * rtf)
          ROS_WARN("simulator: achieved real-time factor %.2f of %.2f requested", achieved, rtf);
        else if (rtf == 0.0)
          ROS_INFO("simulator: as fast as the machine goes: real-time factor %.2f (machine %.0f %% busy, boards "
                   "polled at %.0f of %.0f requests per simulated second)",
                   achieved, 100.0 * machine.lastBusy(), keeping_up.rate(), keeping_up.reference());
        last_report = now;
        report_sim = t;
      }
      if (rtf == 0.0 && now - last_pace > std::chrono::seconds(1)) {
        last_pace = now;
        const bool lagging = keeping_up.lagging(emulatorPolls(), t);
        // Without emulators (a world-only test) there is no request rate to wait for.
        if (machine.update(lagging, !host_ || keeping_up.mayRise())) {
          pace = machine.factor();
          anchor_wall = now;  // the new factor counts from here
          anchor_sim = t;
        }
      }
      {
        const auto target = anchor_wall + std::chrono::duration_cast<Clock::duration>(
                                              std::chrono::duration<double>((t - anchor_sim) / pace));
        if (target > now + std::chrono::microseconds(200)) {
          std::this_thread::sleep_until(target);
        } else if (now - target > std::chrono::milliseconds(200)) {
          // Cannot keep up: run on from here instead of racing to catch up.
          anchor_wall = now;
          anchor_sim = t;
        }
      }
    }
  }

  unsigned long emulatorPolls() const {
    unsigned long n = 0;
    if (host_)
      for (const auto& kv : host_->all()) n += kv.second->polls();
    return n;
  }

  void publishClock(double t) {
    rosgraph_msgs::Clock c;
    c.clock = ros::Time(t);
    // Our own emulators get it through their /clock subscription like every node: setting
    // ros::Time here as well would race that subscription and make time step backwards.
    clock_pub_.publish(c);
  }

  void publishTruth(double t) {
    const ros::Time stamp(t);
    if (truth_rate_.due(t)) {
      truth_pub_.publish(toOdometry(world_->robotTruth(), stamp, "base_link"));
      if (config_.opponent.enabled) opponent_pub_.publish(toOdometry(world_->opponentTruth(), stamp, "opponent"));
    }
    if (elements_rate_.due(t)) elements_pub_.publish(toElementsMsg(world_->elements(), stamp));
    if (match_rate_.due(t)) {
      const MatchProgress m = world_->match();
      match_pub_.publish(toMatchMsg(m, config_.match.year, stamp));
      std_msgs::Int32 score;
      score.data = m.score_ours;
      score_pub_.publish(score);
      if (world_->scoreEventCount() != published_events_) {  // copied only when there is news
        const std::vector<RefereeEvent> events = world_->scoreEvents();
        score_events_pub_.publish(toScoreEventsMsg(events, stamp));
        published_events_ = events.size();
      }
    }
    if (marker_rate_.due(t) && markers_pub_.getNumSubscribers() > 0)
      markers_pub_.publish(worldMarkers(config_, world_->snapshot(), stamp));
  }

  void publishFaults() {
    ActiveFaults m;
    m.header.stamp = ros::Time(world_->time());
    for (const auto& f : faults_.active()) {
      m.kinds.push_back(f.kind);
      m.targets.push_back(f.target);
      m.ends.push_back(f.open() ? 0.0 : f.end);
    }
    faults_pub_.publish(m);
  }

  // ------------------------------------------------------------ inputs
  void onBrainStatus(const smart_brain::MatchStatus& m) {
    if (m.state == "running" && world_->startMatch())
      ROS_INFO("simulator: the brain started the match without the cord: start cord pulled");
  }

  void onMotorCommand(const DebugMotorCommand& m) {
    if (m.motors.size() != m.fractions.size()) {
      ROS_WARN_THROTTLE(5, "simulator: /sim/debug/motor_command with %zu motors and %zu fractions dropped",
                        m.motors.size(), m.fractions.size());
      return;
    }
    for (std::size_t i = 0; i < m.motors.size(); ++i) {
      if (!world_->has("motor", m.motors[i])) {
        ROS_WARN_THROTTLE(5, "simulator: /sim/debug/motor_command: no motor named '%s'", m.motors[i].c_str());
        continue;
      }
      if (m.at > world_->time()) world_->scheduleMotorCommand(m.at, m.motors[i], m.fractions[i]);
      else world_->setMotorCommand(m.motors[i], m.fractions[i]);
    }
  }

  bool onInjectFault(InjectFault::Request& req, InjectFault::Response& res) {
    FaultEntry f;
    f.kind = req.kind;
    f.target = req.target;
    f.magnitude = req.magnitude;
    if (req.clear) {
      res.ok = faults_.clear(f.kind, f.target);
      res.message = res.ok ? "cleared" : "no such fault scheduled or active";
      return true;
    }
    if (!std::isfinite(req.start) || !std::isfinite(req.duration) || req.duration < 0.0) {
      res.ok = false;
      res.message = "start must be finite and duration >= 0";
      return true;
    }
    std::string why;
    if (!validFault(f, true, &why)) {
      res.ok = false;
      res.message = why;
      return true;
    }
    const double now = world_->time();
    f.start = std::max(req.start, now);
    f.end = req.duration > 0.0 ? f.start + req.duration : 0.0;
    if (req.start <= now) {
      // Now: apply here so the caller learns at once whether the target emulates it.
      if (!applyFault(f, true, &why)) {
        res.ok = false;
        res.message = why;
        return true;
      }
      f.active = true;
    }
    faults_.add(f);
    publishFaults();
    res.ok = true;
    res.message = f.active ? "active" : "scheduled";
    return true;
  }

  bool onTable(double x, double y) const {
    return x >= 0.0 && x <= config_.table.length && y >= 0.0 && y <= config_.table.width;
  }

  bool onTeleport(Teleport::Request& req, Teleport::Response& res) {
    if (!onTable(req.pose.x, req.pose.y) || !std::isfinite(req.pose.theta)) {
      res.ok = false;
      res.message = "pose off the table";
      return true;
    }
    world_->teleport(Pose2D{req.pose.x, req.pose.y, req.pose.theta});
    res.ok = true;
    return true;
  }

  bool onPlaceOpponent(PlaceOpponent::Request& req, PlaceOpponent::Response& res) {
    if (!config_.opponent.enabled || !onTable(req.pose.x, req.pose.y) || !std::isfinite(req.pose.theta)) {
      res.ok = false;
      res.message = config_.opponent.enabled ? "pose off the table" : "the opponent is disabled";
      return true;
    }
    world_->placeOpponent(Pose2D{req.pose.x, req.pose.y, req.pose.theta}, req.hold);
    res.ok = true;
    return true;
  }

  bool onSetSwitch(SetSwitch::Request& req, SetSwitch::Response& res) {
    res.ok = world_->setSwitch(req.name, req.closed);
    if (!res.ok) res.message = "'" + req.name + "' is not a manual switch under sim/world/robot/switches";
    return true;
  }


  bool onSetRealTimeFactor(SetRealTimeFactor::Request& req, SetRealTimeFactor::Response& res) {
    if (!SimulatorSettings::validFactor(req.real_time_factor)) {
      res.ok = false;
      res.message = std::string("real_time_factor ") + SimulatorSettings::kFactorRule + ", got " + std::to_string(req.real_time_factor);
      return true;
    }
    const double before = rtf_.exchange(req.real_time_factor);
    res.ok = true;
    char text[128];
    std::snprintf(text, sizeof text, "real-time factor %g (was %g)", req.real_time_factor, before);
    res.message = text;
    ROS_INFO("simulator: %s at t=%.3f", text, world_->time());
    return true;
  }

  bool onPause(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res) {
    paused_ = req.data;
    res.success = true;
    res.message = req.data ? "paused" : "running";
    return true;
  }

  ros::NodeHandle nh_, pnh_;
  WorldConfig config_;
  std::unique_ptr<SimWorld> world_;
  std::unique_ptr<FirmwareHost> host_;
  FaultSchedule faults_;
  SimulatorSettings settings_;
  std::atomic<double> rtf_{1.0};  // requested: set at start and by ~set_real_time_factor
  std::atomic<bool> paused_{false};
  std::atomic<bool> running_{false};
  SimRate truth_rate_, elements_rate_, match_rate_, marker_rate_;
  std::thread thread_;
  ros::Publisher clock_pub_, truth_pub_, opponent_pub_, elements_pub_, match_pub_, score_pub_, score_events_pub_, faults_pub_,
      markers_pub_;
  std::size_t published_events_ = 0;
  ros::Subscriber brain_sub_;
  ros::Subscriber motor_sub_;
  std::vector<ros::ServiceServer> services_;
};

}  // namespace robot_sim

int main(int argc, char** argv) {
  ros::init(argc, argv, "simulator");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  robot_sim::Simulator sim(nh, pnh);
  if (!sim.start()) return 1;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ros::waitForShutdown();
  return 0;
}
