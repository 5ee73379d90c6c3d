#include "hcl_drivers/canopen/remote_node.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "hcl_drivers/canopen/cob_id.h"

namespace hcl_drivers {
namespace canopen {

using transport::CanFrame;
using transport::CanFilter;

namespace {
double nowS() {  // reply windows: wall time
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
std::string hex(uint32_t v, int width = 4) {
  char b[16];
  std::snprintf(b, sizeof(b), "0x%0*X", width, v);
  return b;
}
}  // namespace

RemoteNode::RemoteNode(std::shared_ptr<transport::CanBus> bus, uint8_t node_id, const std::vector<uint32_t>& extra_cob_ids)
    : bus_(std::move(bus)), node_id_(node_id) {
  std::vector<CanFilter> filters{CanFilter{node_id_, 0x07F, false}};
  for (uint32_t id : extra_cob_ids)
    if (nodeOf(id) != node_id_) filters.push_back(CanFilter{id, 0x7FF, false});
  channel_ = bus_->open(filters);
}

bool RemoteNode::sendRaw(const CanFrame& f) {
  if (!channel_->send(f)) {
    last_error_ = channel_->lastError();
    return false;
  }
  return true;
}

bool RemoteNode::nmt(NmtCommand cmd) {
  if (!sendRaw(encodeNmt(cmd, node_id_))) return false;
  if (cmd == NmtCommand::kStart) state_ = NmtState::kOperational;
  if (cmd == NmtCommand::kStop) state_ = NmtState::kStopped;
  if (cmd == NmtCommand::kEnterPreOperational) state_ = NmtState::kPreOperational;
  return true;
}

bool RemoteNode::requestPdo(uint32_t cob_id, uint8_t dlc) { return sendRaw(encodeRtr(cob_id, dlc)); }

double RemoteNode::ageNow() const { return age_clock_ ? age_clock_() : nowS(); }

double RemoteNode::heartbeatAge() const {
  const double t = last_heartbeat_;
  return t < 0 ? -1.0 : ageNow() - t;
}

void RemoteNode::dispatch(const CanFrame& f) {
  if (f.error || f.extended) {
    ++unknown_;
    return;
  }
  auto h = handlers_.find(f.id);
  if (h != handlers_.end()) {
    if (f.rtr) return;  // someone else requesting the same PDO: not data
    if (!h->second(f)) {
      ++malformed_;
      last_error_ = "malformed frame " + transport::toString(f);
    }
    return;
  }
  const uint32_t fn = functionOf(f.id);
  if (nodeOf(f.id) == node_id_ && fn == kHeartbeat) {
    const auto hb = decodeHeartbeat(f);
    if (!hb) {
      ++malformed_;
      last_error_ = "malformed heartbeat " + transport::toString(f);
      return;
    }
    last_heartbeat_ = ageNow();
    heartbeat_state_ = hb->state;
    state_ = hb->state;
    if (hb->bootUp()) {
      ++boot_ups_;
      if (on_boot_up_) on_boot_up_();
    }
    return;
  }
  if (nodeOf(f.id) == node_id_ && fn == kSdoTx) {
    const auto r = decodeSdoResponse(f);
    if (!r) {
      ++malformed_;
      last_error_ = "malformed SDO response " + transport::toString(f);
      return;
    }
    sdo_response_ = r;
    return;
  }
  // Frames the master sends itself (RPDOs, SDO requests) seen from another master, RTRs, or
  // COB-IDs this driver does not know: counted and dropped.
  if (!f.rtr && fn != kRpdo1 && fn != kRpdo2 && fn != kRpdo3 && fn != kRpdo4 && fn != kSdoRx) ++unknown_;
}

bool RemoteNode::waitFor(const std::function<bool()>& done, double timeout_s) {
  const double deadline = nowS() + timeout_s;
  CanFrame f;
  while (true) {
    if (done()) return true;
    const double left = deadline - nowS();
    if (!channel_->receive(f, left > 0 ? left : 0.0)) {
      if (left <= 0) return done();
      continue;  // woke up without a frame before the deadline
    }
    dispatch(f);
  }
}

std::string RemoteNode::sdoName(uint16_t index, uint8_t subindex) const {
  return "SDO " + hex(index) + "sub" + std::to_string(subindex) + " of node " + std::to_string(node_id_);
}

SdoResponse RemoteNode::sdoExchange(const CanFrame& request, uint16_t index, uint8_t subindex, bool segment_phase,
                                    double timeout_s) {
  const std::string what = sdoName(index, subindex);
  sdo_response_.reset();
  if (!sendRaw(request)) throw SdoError(what + ": cannot send: " + last_error_);
  const auto ours = [&](const SdoResponse& r) {
    if (r.kind == SdoResponse::Kind::kAbort || !segment_phase) return r.index == index && r.subindex == subindex;
    return r.segment();
  };
  const bool got = waitFor([&] { return sdo_response_ && ours(*sdo_response_); }, timeout_s);
  if (!got) {
    ++sdo_timeouts_;
    const std::string why = "no answer within " + std::to_string(static_cast<int>(timeout_s * 1e3)) + " ms";
    if (segment_phase) sdoAbortTransfer(index, subindex, sdo_abort::kTimeout, why);
    throw SdoError(what + ": " + why);
  }
  const SdoResponse r = *sdo_response_;
  sdo_response_.reset();
  if (r.kind == SdoResponse::Kind::kAbort) {
    ++sdo_aborts_;
    throw SdoError(what + " aborted: " + describeAbort(r.value), r.value);
  }
  return r;
}

void RemoteNode::sdoAbortTransfer(uint16_t index, uint8_t subindex, uint32_t code, const std::string& why) {
  sendRaw(encodeSdoAbort(node_id_, index, subindex, code));  // best effort: the error is thrown anyway
  throw SdoError(sdoName(index, subindex) + ": " + why + "; aborted by the master: " + describeAbort(code), code);
}

std::vector<uint8_t> RemoteNode::sdoUpload(uint16_t index, uint8_t subindex, double timeout_s) {
  using Kind = SdoResponse::Kind;
  SdoResponse r = sdoExchange(encodeSdoRead(node_id_, index, subindex), index, subindex, false, timeout_s);
  std::vector<uint8_t> out;
  if (r.kind == Kind::kReadData) {
    for (int i = 0; i < r.size; ++i) out.push_back(static_cast<uint8_t>(r.value >> (8 * i)));
    return out;
  }
  if (r.kind != Kind::kUploadSegmented)
    throw SdoError(sdoName(index, subindex) + ": read answered by a write acknowledge");
  const bool size_indicated = r.size_indicated;
  const uint32_t size = r.value;
  if (size_indicated && size > kMaxUploadBytes)
    sdoAbortTransfer(index, subindex, sdo_abort::kOutOfMemory, std::to_string(size) + " bytes announced");
  bool toggle = false;
  while (true) {
    r = sdoExchange(encodeSdoUploadSegmentRequest(node_id_, toggle), index, subindex, true, timeout_s);
    if (r.kind != Kind::kUploadSegment)
      sdoAbortTransfer(index, subindex, sdo_abort::kBadCommand, "a download acknowledge during an upload");
    if (r.toggle != toggle)
      sdoAbortTransfer(index, subindex, sdo_abort::kToggleBit, "segment toggle bit " + std::to_string(r.toggle));
    out.insert(out.end(), r.data.begin(), r.data.begin() + r.size);
    if (out.size() > kMaxUploadBytes)
      sdoAbortTransfer(index, subindex, sdo_abort::kOutOfMemory, "more than " + std::to_string(kMaxUploadBytes) + " bytes");
    if (r.last) break;
    toggle = !toggle;
  }
  if (size_indicated && out.size() != size)
    throw SdoError(sdoName(index, subindex) + ": " + std::to_string(out.size()) + " bytes received, " +
                   std::to_string(size) + " announced");
  return out;
}

void RemoteNode::sdoDownload(uint16_t index, uint8_t subindex, const std::vector<uint8_t>& data, double timeout_s) {
  using Kind = SdoResponse::Kind;
  if (!data.empty() && data.size() <= 4) {
    uint32_t v = 0;
    for (std::size_t i = 0; i < data.size(); ++i) v |= static_cast<uint32_t>(data[i]) << (8 * i);
    sdoWrite(index, subindex, v, static_cast<uint8_t>(data.size()), timeout_s);
    return;
  }
  const SdoResponse r = sdoExchange(encodeSdoDownloadInitiate(node_id_, index, subindex, static_cast<uint32_t>(data.size())),
                                    index, subindex, false, timeout_s);
  if (r.kind != Kind::kWriteAck) throw SdoError(sdoName(index, subindex) + ": write answered by read data");
  bool toggle = false;
  std::size_t at = 0;
  while (true) {
    const uint8_t len = static_cast<uint8_t>(std::min<std::size_t>(7, data.size() - at));
    const bool last = at + len == data.size();
    const SdoResponse a = sdoExchange(encodeSdoDownloadSegment(node_id_, toggle, data.data() + at, len, last), index,
                                      subindex, true, timeout_s);
    if (a.kind != Kind::kDownloadSegmentAck)
      sdoAbortTransfer(index, subindex, sdo_abort::kBadCommand, "an upload segment during a download");
    if (a.toggle != toggle)
      sdoAbortTransfer(index, subindex, sdo_abort::kToggleBit, "acknowledge toggle bit " + std::to_string(a.toggle));
    at += len;
    if (last) return;
    toggle = !toggle;
  }
}

uint32_t RemoteNode::sdoRead(uint16_t index, uint8_t subindex, double timeout_s) {
  const std::vector<uint8_t> b = sdoUpload(index, subindex, timeout_s);
  if (b.size() > 4)
    throw SdoError(sdoName(index, subindex) + ": " + std::to_string(b.size()) + " bytes, not a value of up to 4 bytes");
  uint32_t v = 0;
  for (std::size_t i = 0; i < b.size(); ++i) v |= static_cast<uint32_t>(b[i]) << (8 * i);
  return v;
}

void RemoteNode::sdoWrite(uint16_t index, uint8_t subindex, uint32_t value, uint8_t size, double timeout_s) {
  const SdoResponse r =
      sdoExchange(encodeSdoWrite(node_id_, index, subindex, value, size), index, subindex, false, timeout_s);
  if (r.kind != SdoResponse::Kind::kWriteAck) throw SdoError(sdoName(index, subindex) + ": write answered by read data");
}

}  // namespace canopen
}  // namespace hcl_drivers
