// What every CANopen board driver shares: the bus, the node, NMT start after boot-up, bus-off and
// stale handling, refused commands, diagnostics. A board reads its parameters in readParams(),
// adds its PDOs and topics in setup(), its SDO configuration in configureNode() and its poll in
// exchange(); see motor_board.cpp for the pattern.
//
// Common parameters (besides rate/loop/stale_timeout of board_nodelet.h: ~bus, ~node_id, the
// timeouts, the heartbeat, every PDO's ~<pdo>_cob_id): read and described in configure() and
// cobIdParam() (the table: hcl_drivers/PARAMETERS.md, make docs).
// Boards naming the same bus in one process share one bus object, each with its own filters. A
// node that aborts the heartbeat write (0x1017) has none. The ~heartbeat_timeout default, 3 x
// heartbeat_ms + one poll period (heartbeats are dispatched by the poll), is about the PDO
// staleness of a fast board and well before it for a slow one. The COB-IDs default to CiA 301's
// (0x180/0x200/0x280 + node id).
#pragma once

#include <hcl_drivers/CanNodeStatus.h>
#include <robot_core/held_episode.h>
#include <robot_core/priority_inheritance_mutex.h>

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>

#include "hcl_drivers/board.h"
#include "hcl_drivers/canopen/canopen.h"

namespace hcl_drivers {

class CanopenBoard : public Board {
 public:
  // The common parameters, then the board's own (readParams()), into members; nothing else.
  void configure(const robot_core::Params& params) final;
  // Opens the bus and the node, then setup(), with the values configure() read.
  void init(BoardContext& ctx) final;
  bool service() final;
  void halt() final;
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override;
  // The doctor's probe (canopen_board_check.cpp): SDO reads of 0x1000, 0x1018 (identity),
  // 0x1008/0x100A (name, software version) and a heartbeat; nothing is started or written
  // except the producer heartbeat time, put back as it was.
  void check(BoardContext& ctx, CheckReport& report) final;

 protected:
  using CanFrame = transport::CanFrame;
  // Read the board's own parameters into members (nodeId() is known, cobIdParam() helps) and
  // throw ParameterError on a bad one. Nothing else: it runs with no master and no bus
  // (Board::configure()).
  virtual void readParams(const robot_core::Params& params) = 0;
  // Register PDO handlers (node().onFrame), advertise and subscribe, with the members
  // readParams() filled.
  virtual void setup(BoardContext& ctx) = 0;
  // COB-IDs outside this node's id range that the board must receive (before the node exists).
  virtual std::vector<uint32_t> extraCobIds() const { return {}; }
  // SDO configuration of the node, after start and after every boot-up (throws canopen::SdoError).
  virtual void configureNode() {}
  // One poll: send commands, request PDOs by RTR, wait for them (node().waitFor), publish.
  // Return false after fail("why") when the board did not answer.
  virtual bool exchange() = 0;
  // Put the actuators in their safe state (best effort, the board may be gone).
  virtual void stopActuators() = 0;
  // Publish the latched ~state now (also called when the board goes stale or the bus off).
  virtual void publishState() = 0;
  // Diagnostic values of the board itself.
  virtual void diagnoseBoard(diagnostic_updater::DiagnosticStatusWrapper&) {}

  canopen::RemoteNode& node() { return *node_; }
  int nodeId() const { return node_id_; }
  double answerTimeout() const { return answer_timeout_; }
  double commandTimeout() const { return command_timeout_; }
  double sdoTimeout() const { return sdo_timeout_; }
  // One TPDO to request by RTR: its COB-ID and data length.
  struct PdoRequest {
    uint32_t cob_id;
    uint8_t dlc;
  };
  // The poll's request/answer step every board shares: sends an RTR for each of `pdos`, then
  // dispatches frames until `arrived()` (the handlers saw every answer) or ~answer_timeout.
  // False after fail(): "sending RTR: ..." or "<board> (node N) did not answer the RTR(s) within M ms".
  bool requestPdos(const std::vector<PdoRequest>& pdos, const std::function<bool()>& arrived, const std::string& board);
  // ~<name> as a COB-ID (1..0x7FF), default `fallback` (for readParams()), described as `meaning`.
  static uint32_t cobIdParam(const robot_core::Params& params, const std::string& name, uint32_t fallback,
                             const std::string& meaning);
  // True when the board answers; otherwise counts the refusal and logs `what` (throttled).
  bool acceptCommand(const char* what);
  // Whether a command stamped `stamp` (received at `received`) is still fresh.
  bool fresh(const ros::Time& stamp, const ros::Time& received) const;
  void fillStatus(CanNodeStatus& s);
  const std::string& boardName() const { return name_; }

 private:
  // ~bus and ~node_id, validated (ParameterError naming the parameter otherwise).
  static std::string busParam(const robot_core::Params& params);
  static int nodeIdParam(const robot_core::Params& params);
  std::string url_;  // ~bus
  std::shared_ptr<transport::CanBus> bus_;
  std::unique_ptr<canopen::RemoteNode> node_;
  std::string name_;
  int node_id_ = 0;
  double answer_timeout_ = 0.02, sdo_timeout_ = 0.05, command_timeout_ = 0.25, stale_timeout_ = 0.3;
  // The node's device name (0x1008, a string read by segmented SDO at configuration); CiA 301
  // makes it optional, so a node that aborts the read shows why instead.
  void readDeviceName();
  // Writes 0x1017 (heartbeat_ms_) and starts watching heartbeats from now.
  void configureHeartbeat();
  // Seconds without a heartbeat beyond heartbeat_timeout_ (0 when fine or not watched).
  double heartbeatSilence() const;
  int heartbeat_ms_ = 100;
  double heartbeat_timeout_ = 0.3;
  std::atomic<bool> heartbeat_watched_{false};
  std::atomic<double> heartbeat_configured_at_{0.0};  // ROS time [s]
  std::string device_name_;
  bool need_start_ = true;
  bool need_configure_ = true;
  int consecutive_failures_ = 0;
  ros::Time last_ok_;
  std::atomic<bool> answering_{false};
  bool was_answering_ = false;
  std::atomic<unsigned long> refused_{0};
  transport::BusState last_bus_state_ = transport::BusState::kErrorActive;
  // Transients diagnose() holds at ERROR (a bus-off recovered from, a reset, malformed frames).
  // Only the diagnostics' checks touch these, one at a time.
  robot_core::HeldEpisode bus_off_, resets_, malformed_;
  bool checked_ = false;          // a first check took the counts as they were
  bool answered_before_ = false;  // the board answered by the previous check: boot-ups are resets from then
  robot_core::PriorityInheritanceMutex status_mutex_;  // node counters copied for diagnostics/state (loop vs checks)
  CanNodeStatus status_copy_;
};

}  // namespace hcl_drivers
