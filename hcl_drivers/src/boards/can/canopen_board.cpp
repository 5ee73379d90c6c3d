#include "canopen_board.h"

#include <algorithm>

#include "hcl_drivers/transport/endpoint.h"

namespace hcl_drivers {

using robot_core::ParameterError;

using transport::BusState;

std::string CanopenBoard::busParam(const robot_core::Params& p) {
  p.describe("bus", "the CAN bus: socketcan://IFACE or udp://127.0.0.1:PORT (simulation)");
  const std::string url = p.requireString("bus");
  try {
    const auto ep = transport::parseEndpoint(url);
    if (ep.scheme != "socketcan" && ep.scheme != "udp") throw std::invalid_argument("not a CAN bus");
  } catch (const std::invalid_argument&) {
    throw ParameterError("parameter " + p.qualified("bus") + " = '" + url +
                         "': allowed values: socketcan://IFACE or udp://127.0.0.1:PORT");
  }
  return url;
}

int CanopenBoard::nodeIdParam(const robot_core::Params& p) {
  p.describe("node_id", "CANopen node id of the board, 1..127");
  const int id = p.requireInt("node_id");
  if (!canopen::validNodeId(id))
    throw ParameterError("parameter " + p.qualified("node_id") + " = " + std::to_string(id) +
                         ": must be a CANopen node id 1..127");
  return id;
}

void CanopenBoard::configure(const robot_core::Params& p) {
  // The polling rate, for the defaults below: required and checked by the framework
  // (BoardSettings) before configure(); the doctor polls nothing and takes 10 Hz when absent.
  p.describe("rate", "[Hz] polling rate of the board");
  const double rate = p.optionalDouble("rate", 10.0);
  p.requirePositive("rate", rate);
  url_ = busParam(p);
  node_id_ = nodeIdParam(p);
  p.describe("answer_timeout", "[s] wait for the PDOs requested by RTR in a poll");
  answer_timeout_ = p.optionalDouble("answer_timeout", std::min(0.02, 0.5 / rate));
  p.requirePositive("answer_timeout", answer_timeout_);
  p.describe("sdo_timeout", "[s] wait for an SDO answer");
  sdo_timeout_ = p.optionalDouble("sdo_timeout", 0.05);
  p.requirePositive("sdo_timeout", sdo_timeout_);
  p.describe("command_timeout", "[s] a command older than this is dropped and the actuator stopped");
  command_timeout_ = p.optionalDouble("command_timeout", 0.25);
  p.requirePositive("command_timeout", command_timeout_);
  p.describe("stale_timeout", "[s] no good exchange for this long = STALE; when absent max(0.3, 3 / rate)");
  stale_timeout_ = p.optionalDouble("stale_timeout", std::max(0.3, 3.0 / rate));
  p.describe("heartbeat_ms",
             "[ms] producer heartbeat time written to the node (0x1017) at configuration; 0 = off");
  heartbeat_ms_ = p.optionalInt("heartbeat_ms", 100);
  p.requireInRange("heartbeat_ms", heartbeat_ms_, 0, 10000);
  p.describe("heartbeat_timeout",
             "[s] no heartbeat for this long: STALE and commands refused, before the PDO staleness");
  heartbeat_timeout_ = p.optionalDouble("heartbeat_timeout", 3.0 * heartbeat_ms_ / 1000.0 + 1.0 / rate);
  p.requirePositive("heartbeat_timeout", heartbeat_timeout_);
  // The board's own parameters too, so a bad one stops the node before the bus is opened.
  readParams(p);
}

void CanopenBoard::init(BoardContext& ctx) {
  name_ = ctx.name;
  try {
    bus_ = transport::openCanBus(url_);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot open CAN bus " + url_ + ": " + e.what());
  }
  // setup() registers handlers on node(): the node must exist; its extra filters come first.
  node_.reset();
  std::vector<uint32_t> extra = extraCobIds();
  node_ = std::make_unique<canopen::RemoteNode>(bus_, static_cast<uint8_t>(node_id_), extra);
  node_->setAgeClock([] { return ros::Time::now().toSec(); });  // heartbeat ages: ROS time
  setup(ctx);
  node_->onBootUp([this] {
    ROS_WARN("%s: boot-up message from node %d: the board reset; restarting it", name_.c_str(), node_id_);
    need_start_ = need_configure_ = true;
  });
  last_ok_ = ros::Time::now();
}

uint32_t CanopenBoard::cobIdParam(const robot_core::Params& p, const std::string& name, uint32_t fallback,
                                  const std::string& meaning) {
  p.describe(name, meaning);
  const int v = p.optionalInt(name, static_cast<int>(fallback));
  if (v < 1 || v > 0x7FF)
    throw ParameterError("parameter " + p.qualified(name) + " = " + std::to_string(v) +
                         ": must be an 11-bit COB-ID 0x001..0x7FF");
  return static_cast<uint32_t>(v);
}

bool CanopenBoard::requestPdos(const std::vector<PdoRequest>& pdos, const std::function<bool()>& arrived,
                               const std::string& board) {
  for (const auto& p : pdos)
    if (!node_->requestPdo(p.cob_id, p.dlc)) {
      fail("sending RTR: " + node_->lastError());
      return false;
    }
  if (node_->waitFor(arrived, answer_timeout_)) return true;
  fail(board + " (node " + std::to_string(node_id_) + ") did not answer the " + (pdos.size() == 1 ? "RTR" : "RTRs") +
       " within " + std::to_string(static_cast<int>(answer_timeout_ * 1e3)) + " ms");
  return false;
}

bool CanopenBoard::acceptCommand(const char* what) {
  if (answering_) return true;
  ++refused_;
  ROS_WARN_THROTTLE(1.0, "%s: board (node %d) not answering: %s command refused", name_.c_str(), node_id_, what);
  return false;
}

bool CanopenBoard::fresh(const ros::Time& stamp, const ros::Time& received) const {
  const ros::Time now = ros::Time::now();
  if (received.isZero()) return false;
  if ((now - received).toSec() > command_timeout_) return false;
  if (!stamp.isZero() && (now - stamp).toSec() > command_timeout_) return false;
  return true;
}

void CanopenBoard::fillStatus(CanNodeStatus& s) {
  s.node_id = static_cast<uint8_t>(node_id_);
  s.nmt_state = canopen::toString(node_->state());
  s.answering = answering_;
  const auto bs = bus_->status();
  s.bus_state = transport::toString(bs.state);
  s.boot_ups = static_cast<uint32_t>(node_->bootUps());
  s.malformed_frames = static_cast<uint32_t>(node_->malformed());
  s.unknown_frames = static_cast<uint32_t>(node_->unknownCobIds());
  s.sdo_aborts = static_cast<uint32_t>(node_->sdoAborts());
  s.commands_refused = static_cast<uint32_t>(refused_);
  s.last_error = lastError();
  std::lock_guard lk(status_mutex_);
  status_copy_ = s;
}

bool CanopenBoard::service() {
  const auto bus = bus_->status();
  bool ok = false;
  if (bus.state == BusState::kBusOff) {
    // Nothing can be sent; still read what arrives (a received frame means the bus is back).
    node_->pump();
    fail("CAN bus " + bus_->url() + " is bus-off (" + bus.last_error + ")");
  } else {
    node_->pump();  // boot-ups and heartbeats that arrived between polls
    try {
      if (need_start_) {
        if (!node_->nmt(canopen::NmtCommand::kStart)) throw std::runtime_error("NMT start: " + node_->lastError());
        need_start_ = false;
      }
      if (need_configure_) {
        readDeviceName();
        configureHeartbeat();
        configureNode();
        need_configure_ = false;
      }
      const double silence = heartbeatSilence();
      ok = exchange();
      if (silence > 0) {
        // The node's heartbeat stopped: it is lost (CiA 301) even if a PDO still came. If it
        // did answer, it may have reset unseen (heartbeat off again): configure it again.
        if (ok) need_configure_ = true;
        fail("no heartbeat from node " + std::to_string(node_id_) + " for " + std::to_string(static_cast<int>(silence * 1e3)) +
             " ms (producer time " + std::to_string(heartbeat_ms_) + " ms)");
        answering_ = false;
        ok = false;
      }
    } catch (const std::exception& e) {
      fail(e.what());
      ok = false;
    }
  }
  const ros::Time now = ros::Time::now();
  if (ok) {
    last_ok_ = now;
    consecutive_failures_ = 0;
    answering_ = true;
  } else {
    // A node that reset without us seeing its boot-up sits in pre-operational and ignores RTRs:
    // start it again (cheap, idempotent).
    if (++consecutive_failures_ >= 2) need_start_ = true;
    if ((now - last_ok_).toSec() > stale_timeout_) answering_ = false;
  }
  const bool state_changed = bus.state != last_bus_state_ || answering_ != was_answering_;
  last_bus_state_ = bus.state;
  was_answering_ = answering_;
  if (!ok && state_changed) publishState();  // faults show on the state topic too
  return ok;
}

void CanopenBoard::readDeviceName() {
  std::string name;
  try {
    const std::vector<uint8_t> b = node_->sdoUpload(canopen::kDeviceNameIndex, 0, sdo_timeout_);
    name.assign(b.begin(), b.end());
  } catch (const canopen::SdoError& e) {
    // Optional in CiA 301, and some boards have no SDO server at all (the VM test's can-utils
    // node): never fatal; whether the node answers is the PDO exchange's business.
    name = std::string("(not read: ") + e.what() + ")";
  }
  std::lock_guard lk(status_mutex_);
  device_name_ = name;
}

void CanopenBoard::configureHeartbeat() {
  heartbeat_watched_ = false;
  if (heartbeat_ms_ == 0) return;
  try {
    node_->sdoWrite(canopen::kProducerHeartbeatIndex, 0, static_cast<uint32_t>(heartbeat_ms_), 2, sdo_timeout_);
  } catch (const canopen::SdoError& e) {
    // Aborted or unanswered (a node without an SDO server): run without heartbeat watching
    // until the next boot-up configures the node again.
    ROS_WARN("%s: node %d has no producer heartbeat (%s): not watched", name_.c_str(), node_id_, e.what());
    return;
  }
  heartbeat_configured_at_ = ros::Time::now().toSec();
  heartbeat_watched_ = true;
}

double CanopenBoard::heartbeatSilence() const {
  if (!heartbeat_watched_) return 0.0;
  const double hb_age = node_->heartbeatAge();
  const double since_configured = ros::Time::now().toSec() - heartbeat_configured_at_;
  const double silence = hb_age < 0 ? since_configured : std::min(hb_age, since_configured);
  return silence > heartbeat_timeout_ ? silence : 0.0;
}

void CanopenBoard::halt() {
  if (!node_) return;
  answering_ = false;
  try {
    stopActuators();
  } catch (const std::exception& e) {
    ROS_ERROR("%s: stopping actuators failed: %s", name_.c_str(), e.what());
  }
}

void CanopenBoard::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  const auto bs = bus_->status();
  {
    std::lock_guard lk(status_mutex_);
    stat.add("node id", node_id_);
    stat.add("device name", device_name_);
    stat.add("NMT state", status_copy_.nmt_state);
    stat.add("boot-ups seen", status_copy_.boot_ups);
    stat.add("malformed frames", status_copy_.malformed_frames);
    stat.add("unknown COB-ID frames", status_copy_.unknown_frames);
    stat.add("SDO aborts", status_copy_.sdo_aborts);
  }
  stat.add("commands refused", refused_.load());
  stat.add("NMT state (heartbeat)", canopen::toString(node_->heartbeatState()));
  stat.add("heartbeat producer time [ms]", heartbeat_watched_ ? heartbeat_ms_ : 0);
  stat.addf("heartbeat age [ms]", "%.0f", 1e3 * node_->heartbeatAge());
  // Checked here too, on the diagnostics timer: a slow poll must not delay the report. The cause
  // first: a bus-off controller hears no heartbeat either, and the poll that would say so may
  // not have run since the bus went off.
  const double silence = heartbeatSilence();
  if (bs.state == BusState::kBusOff)
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::ERROR, "CAN bus %s is bus-off (%s)", bus_->url().c_str(),
                  bs.last_error.c_str());
  else if (silence > 0)
    stat.summaryf(diagnostic_msgs::DiagnosticStatus::STALE, "no heartbeat from node %d for %.0f ms (producer time %d ms)",
                  node_id_, 1e3 * silence, heartbeat_ms_);
  stat.add("bus", bus_->url());
  stat.add("bus state", transport::toString(bs.state));
  stat.add("bus error frames", bs.error_frames);
  stat.add("bus-off events", bs.bus_off_count);
  stat.add("controller restarts", bs.restarts);
  stat.add("bus rx frames", bs.rx_frames);
  stat.add("bus tx frames", bs.tx_frames);
  stat.add("bus tx failures", bs.tx_failures);
  stat.add("bus malformed datagrams", bs.malformed);
  stat.add("bus queue overruns", bs.overruns);
  if (!bs.last_error.empty()) stat.add("bus last error", bs.last_error);
  // A bus-off the controller recovered from, a reset or a malformed frame is over at once (the
  // driver re-configured the board / dropped the frame): each is held at ERROR for a second after
  // the last check that saw one more, counted over the episode (robot_core/held_episode.h), so a
  // team (and a bag) sees it, then the board is OK again.
  uint32_t boot_ups, malformed;
  {
    std::lock_guard lk(status_mutex_);
    boot_ups = status_copy_.boot_ups;
    malformed = status_copy_.malformed_frames;
  }
  const ros::Time now = ros::Time::now();
  if (checked_) {  // the first check takes the counts as they are: the power-on's, a bus's past
    bus_off_.see(bs.bus_off_count, now);
    malformed_.see(malformed, now);
  } else {
    bus_off_.take(bs.bus_off_count);
    malformed_.take(malformed);
  }
  // Boot-ups before the board first answered are its power-on, not a reset.
  if (checked_ && answered_before_)
    resets_.see(boot_ups, now);
  else
    resets_.take(boot_ups);
  checked_ = true;
  answered_before_ = answered_before_ || answering_;
  if (bus_off_.shown(now) && bs.state != BusState::kBusOff)
    stat.mergeSummaryf(diagnostic_msgs::DiagnosticStatus::ERROR, "CAN bus %s was bus-off %lu time(s) (now %s)",
                       bus_->url().c_str(), bus_off_.count(), transport::toString(bs.state));
  if (resets_.shown(now))
    stat.mergeSummaryf(diagnostic_msgs::DiagnosticStatus::ERROR, "the board reset: %lu boot-up(s) of node %d (re-configured)",
                       resets_.count(), node_id_);
  if (malformed_.shown(now))
    stat.mergeSummaryf(diagnostic_msgs::DiagnosticStatus::ERROR, "%lu malformed frame(s) from node %d (dropped)",
                       malformed_.count(), node_id_);
  diagnoseBoard(stat);
}

}  // namespace hcl_drivers
