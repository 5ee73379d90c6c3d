// The master's view of one CANopen node on a CAN bus: NMT commands, expedited and segmented SDO with
// timeouts (abort codes thrown as SdoError), PDO send, PDO request by RTR, receive callbacks
// by COB-ID, and heartbeat/boot-up consumption (a boot-up means the node reset: its
// variables restarted and it waits in pre-operational for an NMT start).
//
// Single-threaded by design: every call is made from the board's polling thread; frames are
// dispatched to the callbacks only inside pump()/waitFor()/sdoRead()/sdoWrite().
#pragma once

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "hcl_drivers/canopen/nmt.h"
#include "hcl_drivers/canopen/pdo.h"
#include "hcl_drivers/canopen/sdo.h"
#include "hcl_drivers/transport/can_bus.h"

namespace hcl_drivers {
namespace canopen {

class RemoteNode {
 public:
  // Returns false when the frame was malformed (wrong length): it is counted and dropped.
  using Handler = std::function<bool(const transport::CanFrame&)>;

  // Opens a channel on `bus` receiving this node's COB-IDs (id & 0x7F == node) plus the
  // extra COB-IDs given (for PDOs mapped elsewhere, e.g. EPOS).
  RemoteNode(std::shared_ptr<transport::CanBus> bus, uint8_t node_id, const std::vector<uint32_t>& extra_cob_ids = {});

  uint8_t nodeId() const { return node_id_; }

  // Callbacks for PDOs (or any COB-ID) this node sends.
  void onFrame(uint32_t cob_id, Handler h) { handlers_[cob_id] = std::move(h); }
  // Called when a boot-up message arrives (the node reset).
  void onBootUp(std::function<void()> h) { on_boot_up_ = std::move(h); }

  bool nmt(NmtCommand cmd);
  bool requestPdo(uint32_t cob_id, uint8_t dlc);
  bool sendRaw(const transport::CanFrame& f);

  // Throw SdoError on abort (with its code), timeout, or a malformed/unexpected answer.
  // sdoRead/sdoWrite: objects of up to 4 bytes (an answer longer than 4 bytes is an error).
  uint32_t sdoRead(uint16_t index, uint8_t subindex, double timeout_s);
  void sdoWrite(uint16_t index, uint8_t subindex, uint32_t value, uint8_t size, double timeout_s);
  // Any length: expedited when the node answers so (upload) or data has 1..4 bytes (download),
  // segmented otherwise. `timeout_s` applies to each request/response pair; the master aborts
  // the transfer (0x05040000) when one times out, and (0x05030000) on a toggle bit error.
  std::vector<uint8_t> sdoUpload(uint16_t index, uint8_t subindex, double timeout_s);
  void sdoDownload(uint16_t index, uint8_t subindex, const std::vector<uint8_t>& data, double timeout_s);
  // Longest segmented upload accepted (the master aborts with "out of memory" beyond it).
  static constexpr std::size_t kMaxUploadBytes = 4096;

  // Dispatches received frames until `done()` is true (returns true) or the timeout passes.
  bool waitFor(const std::function<bool()>& done, double timeout_s);
  // Dispatches the frames already received, without waiting.
  void pump() { waitFor([] { return false; }, 0.0); }

  // Last NMT state reported by the node's heartbeat (kUnknown until one arrives; kBootUp after a reset).
  NmtState state() const { return state_; }
  // The master's belief after commands: operational once started, pre-op after a boot-up.
  void assumeState(NmtState s) { state_ = s; }
  // What the node's own heartbeats (and boot-up) said, readable from any thread: its NMT state
  // and the seconds since the last one was dispatched (negative when none yet).
  NmtState heartbeatState() const { return heartbeat_state_; }
  double heartbeatAge() const;
  unsigned long bootUps() const { return boot_ups_; }
  unsigned long malformed() const { return malformed_; }
  unsigned long unknownCobIds() const { return unknown_; }
  unsigned long sdoAborts() const { return sdo_aborts_; }
  unsigned long sdoTimeouts() const { return sdo_timeouts_; }
  // The clock of the heartbeat age above: monotonic by default; a board node
  // gives ROS time, so a node's heartbeat period means the same at any simulated speed. SDO
  // reply windows stay on the monotonic clock: the other end answers in wall time.
  void setAgeClock(std::function<double()> clock) { age_clock_ = std::move(clock); }
  const std::string& lastError() const { return last_error_; }
  transport::CanBus& bus() { return *bus_; }

 private:
  void dispatch(const transport::CanFrame& f);
  double ageNow() const;
  // Sends `request` and waits for the answer: in the initiate phase one naming index/subindex, in
  // the segment phase a segment frame (or an abort of this transfer). Throws on abort/timeout.
  SdoResponse sdoExchange(const transport::CanFrame& request, uint16_t index, uint8_t subindex, bool segment_phase,
                          double timeout_s);
  // The master's abort of a transfer in progress: sent to the node, then thrown.
  [[noreturn]] void sdoAbortTransfer(uint16_t index, uint8_t subindex, uint32_t code, const std::string& why);
  std::string sdoName(uint16_t index, uint8_t subindex) const;

  std::shared_ptr<transport::CanBus> bus_;
  std::shared_ptr<transport::CanChannel> channel_;
  uint8_t node_id_;
  std::map<uint32_t, Handler> handlers_;
  std::function<void()> on_boot_up_;
  std::optional<SdoResponse> sdo_response_;
  NmtState state_ = NmtState::kUnknown;
  unsigned long boot_ups_ = 0;
  unsigned long malformed_ = 0;
  unsigned long unknown_ = 0;
  unsigned long sdo_aborts_ = 0;
  unsigned long sdo_timeouts_ = 0;
  std::function<double()> age_clock_;
  std::atomic<NmtState> heartbeat_state_{NmtState::kUnknown};
  std::atomic<double> last_heartbeat_{-1.0};
  std::string last_error_;
};

}  // namespace canopen
}  // namespace hcl_drivers
