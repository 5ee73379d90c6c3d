#include "canopen_firmware.h"

#include <robot_core/realtime.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace robot_sim {

using hcl_drivers::transport::CanFilter;

namespace {
// linux/can/error.h error classes, written here from the kernel header's values.
constexpr uint32_t kErrBusOff = 0x040;
constexpr uint32_t kErrRestarted = 0x100;
constexpr uint8_t kBootUp = 0x00, kStopped = 0x04, kOperational = 0x05, kPreOperational = 0x7F;
const char* nmtName(uint8_t s) {
  switch (s) {
    case kBootUp: return "boot-up";
    case kStopped: return "stopped";
    case kOperational: return "operational";
    case kPreOperational: return "pre-operational";
  }
  return "?";
}
}  // namespace

CanopenFirmware::~CanopenFirmware() { stop(); }

double CanopenFirmware::now() const { return firmwareNow(); }

void CanopenFirmware::configure(const robot_core::Params& params) {
  params.describe("bus", "the board's end of the CAN bus: socketcan://IFACE or udp://127.0.0.1:PORT (CAN over UDP), "
                         "the driver's bus in simulation");
  bus_url_ = params.requireString("bus");
  if (bus_url_.rfind("socketcan://", 0) != 0 && bus_url_.rfind("udp://", 0) != 0)
    params.check("bus", "'" + bus_url_ + "' must be socketcan://IFACE or udp://127.0.0.1:PORT");
  params.describe("node_id", "the board's CANopen node id, as the driver's block says");
  const int node = params.requireInt("node_id");
  params.requireInRange("node_id", node, 1, 127);
  node_id_ = static_cast<uint8_t>(node);
  params.describe("bench_ticks_per_s", "without a world (firmware_host): encoder counts per second at full command");
  bench_ticks_per_s_ = params.optionalDouble("bench_ticks_per_s", 4000.0);
  params.describe("bench_range", "[m] without a world: the distance every ranger reads");
  bench_range_ = params.optionalDouble("bench_range", 0.35);
  params.describe("bench_closed", "without a world: the switches that read closed");
  bench_closed_ = params.optionalStringList("bench_closed");
  readBoardParams(params);
}

void CanopenFirmware::start(FirmwareContext& ctx) {
  name_ = ctx.name;
  const std::string url = bus_url_;
  world_ = ctx.world;
  if (!world_) {
    bench_world_ = std::make_unique<BenchWorld>(bench_ticks_per_s_, bench_range_, bench_closed_);
    world_ = bench_world_.get();
  }
  // Common object dictionary entries (CiA 301).
  addObject(0x1000, 0, {4, [] { return 0x00000000u; }, nullptr});        // device type: none
  addObject(0x1001, 0, {1, [] { return 0u; }, nullptr});                 // error register
  addObject(0x1017, 0, {2, [this] { return static_cast<uint32_t>(heartbeat_ms_); },
                        [this](uint32_t v) { heartbeat_ms_ = static_cast<uint16_t>(v); return true; }});
  addObject(0x1018, 1, {4, [] { return 0x0000ED09u; }, nullptr});        // vendor id
  addObject(0x1018, 2, {4, [] { return 0x00000001u; }, nullptr});        // product code
  addObject(0x1018, 3, {4, [] { return 0x00010000u; }, nullptr});        // revision 1.0
  // Longer than 4 bytes: read and written by segmented SDO.
  device_name_ = "robot_sim " + name_;
  addBytesObject(0x1008, 0, {[this] { return device_name_; }, nullptr});  // device name
  addBytesObject(0x100A, 0, {[] { return std::string("robot_sim 1.0"); }, nullptr});  // software version
  addBytesObject(0x2100, 0, {[this] { return user_label_; }, [this](const std::string& v) {
                               if (v.size() > 64) return false;
                               user_label_ = v;
                               return true;
                             }});  // user label, up to 64 bytes
  {
    std::lock_guard<std::mutex> lk(mutex_);
    setupBoard();
  }
  try {
    bus_ = hcl_drivers::transport::openCanBus(url);
    // NMT commands (id 0) and every COB-ID of this node (id & 0x7F == node).
    std::vector<CanFilter> filters{CanFilter{0x000, 0x7FF, false}, CanFilter{node_id_, 0x07F, false}};
    for (uint32_t id : extra_cob_ids_) filters.push_back(CanFilter{id, 0x7FF, false});
    channel_ = bus_->open(filters);
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot open CAN bus " + url + ": " + e.what());
  }
  truth_pub_ = ctx.nh.advertise<CanFirmware>("/sim/" + name_ + "/firmware", 5);
  fault_srv_ = ctx.nh.advertiseService<InjectFault::Request, InjectFault::Response>(
      "/sim/" + name_ + "/inject_fault", [this](InjectFault::Request& req, InjectFault::Response& res) {
        res.ok = applyFault(req.kind, !req.clear);
        res.message = res.ok ? "ok" : "emulator " + name_ + " does not emulate fault '" + req.kind + "'";
        return true;
      });
  truth_timer_ = ctx.nh.createWallTimer(ros::WallDuration(0.05), [this](const ros::WallTimerEvent&) { publishTruth(); });
  running_ = true;
  thread_ = std::thread([this] { run(); });
}

void CanopenFirmware::stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
  truth_timer_.stop();
  channel_.reset();
  bus_.reset();
}

bool CanopenFirmware::applyFault(const std::string& kind, bool active) {
  if (kind == "can_bus_off") {
    if (active == bus_off_) return true;
    bus_off_ = active;
    CanFrame e;
    e.error = true;
    e.dlc = 8;
    e.id = active ? kErrBusOff : kErrRestarted;
    if (channel_) channel_->send(e);
    return true;
  }
  if (kind == "can_reset") {
    if (active) reset_pending_ = true;
    return true;
  }
  if (kind == "can_malformed") {
    if (active) malformed_pending_ = true;
    return true;
  }
  if (boardFault(kind, active)) return true;
  return Firmware::applyFault(kind, active);
}

void CanopenFirmware::send(const CanFrame& f) {
  if (silent() || bus_off_) return;
  channel_->send(f);
}

void CanopenFirmware::powerCycle() {
  resetBoard();
  heartbeat_ms_ = 0;
  nmt_state_ = kPreOperational;
  ++resets_;
  send(CanFrame::make(0x700 + node_id_, {kBootUp}));
}

void CanopenFirmware::run() {
  robot_core::enterRealtime("a CANopen board emulator");  // a board answers like a microcontroller
  {
    std::lock_guard<std::mutex> lk(mutex_);
    resetBoard();
    nmt_state_ = kPreOperational;
    send(CanFrame::make(0x700 + node_id_, {kBootUp}));
  }
  // Frames are answered as they come; every 5 ms of wall time the firmware's timers (heartbeat,
  // watchdog, SDO deadline, the motion model) run on the board's clock (firmwareNow).
  using Wall = std::chrono::steady_clock;
  auto next_tick = Wall::now();
  CanFrame f;
  while (running_) {
    const double wait = std::chrono::duration<double>(next_tick - Wall::now()).count();
    if (channel_->receive(f, wait > 0 ? wait : 0.0)) {
      std::lock_guard<std::mutex> lk(mutex_);
      if (!silent() && !bus_off_) handle(f);
    }
    const auto wall = Wall::now();
    if (wall < next_tick) continue;
    next_tick = wall + std::chrono::milliseconds(5);
    const double t = now();
    std::lock_guard<std::mutex> lk(mutex_);
    if (reset_pending_.exchange(false)) powerCycle();
    if (malformed_pending_.exchange(false)) {
      send(CanFrame::make(0x180 + node_id_, {0xDE, 0xAD, 0xBE}));  // a TPDO with the wrong length
      send(CanFrame::make(0x480 + node_id_, {0x01}));              // TPDO4: not in the driver's map
    }
    tick(t);
    if (transfer_.active && t > transfer_.deadline) {
      transfer_.active = false;
      sdoAbort(transfer_.index, transfer_.sub, 0x05040000);  // SDO protocol timed out
    }
    if (heartbeat_ms_ > 0 && t >= next_heartbeat_) {
      send(CanFrame::make(0x700 + node_id_, {nmt_state_}));
      next_heartbeat_ = t + heartbeat_ms_ / 1000.0;
    }
  }
}

void CanopenFirmware::handle(const CanFrame& f) {
  if (f.extended || f.error) return;
  if (f.id == 0x000) {  // NMT: [command, node (0 = all)]
    if (f.rtr || f.dlc != 2 || (f.data[1] != 0 && f.data[1] != node_id_)) return;
    ++rx_;
    switch (f.data[0]) {
      case 0x01: nmt_state_ = kOperational; break;
      case 0x02: nmt_state_ = kStopped; break;
      case 0x80: nmt_state_ = kPreOperational; break;
      case 0x81: powerCycle(); break;                                       // reset node
      case 0x82: nmt_state_ = kPreOperational; send(CanFrame::make(0x700 + node_id_, {kBootUp})); break;
      default: ++malformed_; break;
    }
    return;
  }
  bool extra = false;
  for (uint32_t id : extra_cob_ids_) extra = extra || id == f.id;
  if ((f.id & 0x7F) != node_id_ && !extra) return;
  const uint32_t fn = f.id & 0x780;
  if (!extra && (fn == 0x700 || fn == 0x580 || fn == 0x080)) return;  // frames this node sends itself
  ++rx_;
  if (!extra && fn == 0x600) {
    if (nmt_state_ == kStopped) return;
    if (f.rtr || f.dlc != 8) {
      ++malformed_;
      return;
    }
    handleSdo(f);
    return;
  }
  if (nmt_state_ != kOperational) return;  // PDOs only in operational
  if (f.rtr) {
    CanFrame out;
    if (onRtr(f.id, out)) {
      ++rtr_;
      countPoll();
      send(out);
    }
    return;
  }
  const RxResult r = onRpdo(f);
  if (r == RxResult::kMalformed) ++malformed_;
}

void CanopenFirmware::sdoAbort(uint16_t index, uint8_t sub, uint32_t code) {
  ++aborts_;
  CanFrame a = CanFrame::make(0x580 + node_id_, {0x80, static_cast<uint8_t>(index), static_cast<uint8_t>(index >> 8), sub, 0, 0, 0, 0});
  put32(a, 4, code);
  send(a);
}

void CanopenFirmware::handleSdo(const CanFrame& f) {
  const uint8_t cmd = f.data[0];
  const uint8_t ccs = cmd >> 5;
  if (ccs == 4) {  // the client aborted: forget the transfer, never answer an abort
    transfer_.active = false;
    return;
  }
  if (ccs == 0 || ccs == 3) return sdoSegment(f);
  const uint16_t index = get16(f, 1);
  const uint8_t sub = f.data[3];
  if (ccs != 1 && ccs != 2) return sdoAbort(index, sub, 0x05040001);  // command specifier unknown
  transfer_.active = false;  // a new initiate ends any transfer in progress
  const uint32_t key = (static_cast<uint32_t>(index) << 8) | sub;
  auto bytes = bytes_od_.find(key);
  if (bytes != bytes_od_.end()) return sdoInitiate(f, bytes->second);
  auto it = od_.find(key);
  if (it == od_.end()) {
    bool index_known = false;
    for (const auto& kv : od_)
      if ((kv.first >> 8) == index) index_known = true;
    for (const auto& kv : bytes_od_)
      if ((kv.first >> 8) == index) index_known = true;
    return sdoAbort(index, sub, index_known ? 0x06090011 : 0x06020000);
  }
  Object& o = it->second;
  if (ccs == 2) {  // upload (read)
    const uint32_t v = o.read();
    CanFrame r = CanFrame::make(0x580 + node_id_, {static_cast<uint8_t>(0x43 | ((4 - o.size) << 2)), f.data[1], f.data[2], sub, 0, 0, 0, 0});
    put32(r, 4, o.size == 4 ? v : (v & ((1u << (8 * o.size)) - 1)));
    send(r);
    return;
  }
  // download (write) of a value: expedited only
  if (!(cmd & 0x02)) return sdoAbort(index, sub, 0x05040001);
  if (!o.write) return sdoAbort(index, sub, 0x06010002);
  if ((cmd & 0x01) && 4 - ((cmd >> 2) & 3) != o.size) return sdoAbort(index, sub, 0x06070010);
  const uint32_t value = o.size == 4 ? get32(f, 4) : (get32(f, 4) & ((1u << (8 * o.size)) - 1));
  if (!o.write(value)) return sdoAbort(index, sub, 0x06090030);
  send(CanFrame::make(0x580 + node_id_, {0x60, f.data[1], f.data[2], sub, 0, 0, 0, 0}));
}

// Initiate on a byte-string object: expedited when it fits in 4 bytes, else a segmented transfer.
void CanopenFirmware::sdoInitiate(const CanFrame& f, BytesObject& o) {
  const uint8_t cmd = f.data[0];
  const uint16_t index = get16(f, 1);
  const uint8_t sub = f.data[3];
  transfer_ = SdoTransfer{};
  transfer_.index = index;
  transfer_.sub = sub;
  transfer_.deadline = now() + 1.0;
  if ((cmd >> 5) == 2) {  // upload
    const std::string v = o.read();
    if (!v.empty() && v.size() <= 4) {
      CanFrame r = CanFrame::make(0x580 + node_id_, {static_cast<uint8_t>(0x43 | ((4 - v.size()) << 2)), f.data[1], f.data[2], sub, 0, 0, 0, 0});
      for (std::size_t i = 0; i < v.size(); ++i) r.data[4 + i] = static_cast<uint8_t>(v[i]);
      send(r);
      return;
    }
    CanFrame r = CanFrame::make(0x580 + node_id_, {0x41, f.data[1], f.data[2], sub, 0, 0, 0, 0});
    put32(r, 4, static_cast<uint32_t>(v.size()));
    transfer_.active = transfer_.upload = true;
    transfer_.data = v;
    send(r);
    return;
  }
  if (!o.write) return sdoAbort(index, sub, 0x06010002);  // read only
  if (cmd & 0x02) {  // expedited download: 4 bytes, or 4 - n when the size is indicated
    const std::size_t n = (cmd & 0x01) ? 4 - ((cmd >> 2) & 3) : 4;
    if (!o.write(std::string(reinterpret_cast<const char*>(f.data.data() + 4), n))) return sdoAbort(index, sub, 0x06070010);
    send(CanFrame::make(0x580 + node_id_, {0x60, f.data[1], f.data[2], sub, 0, 0, 0, 0}));
    return;
  }
  transfer_.active = true;
  transfer_.size_indicated = cmd & 0x01;
  transfer_.size = get32(f, 4);
  send(CanFrame::make(0x580 + node_id_, {0x60, f.data[1], f.data[2], sub, 0, 0, 0, 0}));
}

// One segment request (upload, ccs 3) or segment (download, ccs 0) of the transfer in progress.
void CanopenFirmware::sdoSegment(const CanFrame& f) {
  const uint8_t cmd = f.data[0];
  const bool upload = (cmd >> 5) == 3;
  const bool toggle = cmd & 0x10;
  if (!transfer_.active || transfer_.upload != upload) {
    transfer_.active = false;
    return sdoAbort(transfer_.index, transfer_.sub, 0x05040001);  // no such transfer in progress
  }
  if (toggle != transfer_.toggle) {
    transfer_.active = false;
    return sdoAbort(transfer_.index, transfer_.sub, 0x05030000);  // toggle bit not alternated
  }
  transfer_.toggle = !transfer_.toggle;
  transfer_.deadline = now() + 1.0;
  if (upload) {
    const std::size_t len = std::min<std::size_t>(7, transfer_.data.size() - transfer_.at);
    const bool last = transfer_.at + len == transfer_.data.size();
    CanFrame r = CanFrame::make(0x580 + node_id_, {0, 0, 0, 0, 0, 0, 0, 0});
    r.data[0] = static_cast<uint8_t>((toggle ? 0x10 : 0) | ((7 - len) << 1) | (last ? 1 : 0));
    for (std::size_t i = 0; i < len; ++i) r.data[1 + i] = static_cast<uint8_t>(transfer_.data[transfer_.at + i]);
    transfer_.at += len;
    if (last) transfer_.active = false;
    send(r);
    return;
  }
  const std::size_t len = 7 - ((cmd >> 1) & 7);
  transfer_.data.append(reinterpret_cast<const char*>(f.data.data() + 1), len);
  if (cmd & 0x01) {  // the last segment: the object takes the whole value now
    transfer_.active = false;
    if (transfer_.size_indicated && transfer_.data.size() != transfer_.size)
      return sdoAbort(transfer_.index, transfer_.sub, 0x06070010);
    BytesObject& o = bytes_od_[(static_cast<uint32_t>(transfer_.index) << 8) | transfer_.sub];
    if (!o.write(transfer_.data)) return sdoAbort(transfer_.index, transfer_.sub, 0x06070010);
  }
  send(CanFrame::make(0x580 + node_id_, {static_cast<uint8_t>(0x20 | (toggle ? 0x10 : 0)), 0, 0, 0, 0, 0, 0, 0}));
}

void CanopenFirmware::publishTruth() {
  CanFirmware m;
  m.header.stamp = ros::Time::now();
  {
    std::lock_guard<std::mutex> lk(mutex_);
    m.node_id = node_id_;
    m.nmt_state = nmtName(nmt_state_);
    m.rx_frames = static_cast<uint32_t>(rx_);
    m.rtr_answered = static_cast<uint32_t>(rtr_);
    m.malformed = static_cast<uint32_t>(malformed_);
    m.sdo_aborts = static_cast<uint32_t>(aborts_);
    m.resets = static_cast<uint32_t>(resets_);
    truth(m);
  }
  m.silent = silent();
  m.bus_off = bus_off_;
  truth_pub_.publish(m);
}

}  // namespace robot_sim
