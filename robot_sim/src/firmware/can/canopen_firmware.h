// The firmware side of a CANopen board (CiA 301 subset), shared by the CAN board emulators:
// NMT slave (boot-up message after every reset, pre-operational until NMT start, PDOs only in
// operational), an SDO server (expedited, and segmented with toggle checks and a 1 s segment
// timeout, for the device name 0x1008 and the rw user label 0x2100) over a small object dictionary (aborts for unknown
// indices/subindices, read-only and length mismatches), heartbeat producer (0x1017), RTR
// answers and RPDO reception. Written from the CANopen specification, independently of the
// driver's encoders (hcl_drivers/canopen), so a shared bug cannot hide; only the bus transport
// (hcl_drivers/transport/can_bus.h: SocketCAN or CAN over UDP) is shared with the drivers.
//
// Parameters (sim/firmware/<name>/...): bus, node_id, the bench world's and the board's own
// (robot_sim/PARAMETERS.md).
// Faults (Firmware::applyFault, /sim/inject_fault): board_silent, can_bus_off (an error frame
// "bus-off" on the bus, silent until cleared, then "controller restarted"), can_reset (power
// cycle: boot-up, counters restart), can_malformed (one TPDO of a wrong length and one frame on
// an unknown COB-ID of this node), plus the board's own (EPOS: epos_fault).
// The same faults are also offered per emulator as /sim/<name>/inject_fault (robot_sim/InjectFault:
// kind and clear only), for hosts without the simulator's /sim/inject_fault (firmware_host).
// Truth: /sim/<name>/firmware (robot_sim/CanFirmware) at 20 Hz.
#pragma once

#include <robot_sim/CanFirmware.h>
#include <robot_sim/InjectFault.h>

#include <atomic>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "bench_world.h"
#include "hcl_drivers/transport/can_bus.h"
#include "robot_sim/firmware/firmware.h"

namespace robot_sim {

using hcl_drivers::transport::CanFrame;

class CanopenFirmware : public Firmware {
 public:
  ~CanopenFirmware() override;
  // bus, node_id and the bench world's values, then the board's own (readBoardParams).
  void configure(const robot_core::Params& params) final;
  void start(FirmwareContext& ctx) final;
  void stop() final;
  bool applyFault(const std::string& kind, bool active) override;

 protected:
  // ---- the board's hooks; all run on the emulator thread with mutex() held ----
  // The board's own parameters into members (configure(): no world, no bus; nodeId() is read).
  virtual void readBoardParams(const robot_core::Params& params) = 0;
  virtual void setupBoard() = 0;                      // its objects; throw std::runtime_error when bad
  virtual void resetBoard() = 0;                      // power-on state
  // An RPDO (or any frame with this node's id that is not NMT/SDO): false when it is not one of
  // the board's COB-IDs (counted as unknown) or has the wrong length (counted malformed).
  enum class RxResult { kOk, kUnknown, kMalformed };
  virtual RxResult onRpdo(const CanFrame& f) = 0;
  // The TPDO for an RTR on `cob_id`, or false when the board has no such TPDO.
  virtual bool onRtr(uint32_t cob_id, CanFrame& out) = 0;
  virtual void tick(double now_s) = 0;                // every 5 ms: watchdog, world coupling
  virtual void truth(CanFirmware& m) = 0;             // names/values for /sim/<name>/firmware
  virtual bool boardFault(const std::string&, bool) { return false; }

  // ---- object dictionary: values up to 4 bytes (expedited SDO) ----
  struct Object {
    uint8_t size = 4;
    std::function<uint32_t()> read;
    std::function<bool(uint32_t)> write;  // null: read-only; false: value out of range
  };
  void addObject(uint16_t index, uint8_t sub, Object o) { od_[(static_cast<uint32_t>(index) << 8) | sub] = std::move(o); }
  // ---- and byte strings of any length (expedited when 1..4 bytes, segmented otherwise) ----
  struct BytesObject {
    std::function<std::string()> read;
    std::function<bool(const std::string&)> write;  // null: read-only; false: too long
  };
  void addBytesObject(uint16_t index, uint8_t sub, BytesObject o) {
    bytes_od_[(static_cast<uint32_t>(index) << 8) | sub] = std::move(o);
  }

  // COB-IDs outside this node's id range that the board serves (PDOs mapped elsewhere, EPOS).
  void addExtraCobId(uint32_t cob_id) { extra_cob_ids_.push_back(cob_id); }
  void send(const CanFrame& f);
  uint8_t nodeId() const { return node_id_; }
  bool operational() const { return nmt_state_ == 0x05; }
  World& world() { return *world_; }
  std::mutex& mutex() { return mutex_; }
  double now() const;  // the board's clock (firmwareNow): simulated time in a simulation
  // Little-endian helpers (the board's own, not the driver's).
  static void put16(CanFrame& f, int at, uint16_t v) {
    f.data[at] = static_cast<uint8_t>(v);
    f.data[at + 1] = static_cast<uint8_t>(v >> 8);
  }
  static void put32(CanFrame& f, int at, uint32_t v) {
    for (int i = 0; i < 4; ++i) f.data[at + i] = static_cast<uint8_t>(v >> (8 * i));
  }
  static uint16_t get16(const CanFrame& f, int at) { return static_cast<uint16_t>(f.data[at] | (f.data[at + 1] << 8)); }
  static uint32_t get32(const CanFrame& f, int at) {
    return f.data[at] | (f.data[at + 1] << 8) | (f.data[at + 2] << 16) | (static_cast<uint32_t>(f.data[at + 3]) << 24);
  }
  std::string name_;

 private:
  void run();
  void handle(const CanFrame& f);
  void handleSdo(const CanFrame& f);
  void sdoAbort(uint16_t index, uint8_t sub, uint32_t code);
  void sdoInitiate(const CanFrame& f, BytesObject& o);
  void sdoSegment(const CanFrame& f);
  // A segmented SDO transfer in progress (one at a time, CiA 301 server side).
  struct SdoTransfer {
    bool active = false, upload = false, toggle = false, size_indicated = false;
    uint16_t index = 0;
    uint8_t sub = 0;
    uint32_t size = 0;
    std::string data;
    std::size_t at = 0;
    double deadline = 0.0;  // the client must send its next segment before this
  } transfer_;
  std::string device_name_, user_label_;
  void powerCycle();
  void publishTruth();

  std::shared_ptr<hcl_drivers::transport::CanBus> bus_;
  std::shared_ptr<hcl_drivers::transport::CanChannel> channel_;
  std::string bus_url_;
  double bench_ticks_per_s_ = 4000.0, bench_range_ = 0.35;  // the bench world's, when the host has none
  std::vector<std::string> bench_closed_;
  std::unique_ptr<BenchWorld> bench_world_;  // when the host has no world
  World* world_ = nullptr;
  uint8_t node_id_ = 0;
  std::map<uint32_t, Object> od_;
  std::map<uint32_t, BytesObject> bytes_od_;
  std::vector<uint32_t> extra_cob_ids_;
  std::mutex mutex_;
  uint8_t nmt_state_ = 0x00;
  uint16_t heartbeat_ms_ = 0;
  double next_heartbeat_ = 0.0;
  std::atomic<bool> bus_off_{false};
  std::atomic<bool> running_{false};
  std::atomic<bool> reset_pending_{false}, malformed_pending_{false};
  std::thread thread_;
  ros::Publisher truth_pub_;
  ros::WallTimer truth_timer_;
  ros::ServiceServer fault_srv_;
  unsigned long rx_ = 0, rtr_ = 0, malformed_ = 0, aborts_ = 0, resets_ = 0;
};

}  // namespace robot_sim
