#include "hcl_drivers/canopen/remote_node.h"

#include <chrono>
#include <cstdio>

#include "hcl_drivers/canopen/cob_id.h"

namespace hcl_drivers {
namespace canopen {

using transport::CanFrame;
using transport::CanFilter;

namespace {
double nowS() {
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

bool RemoteNode::sendPdo(uint32_t cob_id, const std::vector<uint8_t>& bytes) { return sendRaw(encodePdo(cob_id, bytes)); }
bool RemoteNode::requestPdo(uint32_t cob_id, uint8_t dlc) { return sendRaw(encodeRtr(cob_id, dlc)); }

double RemoteNode::lastHeardAge() const { return last_heard_ < 0 ? -1.0 : nowS() - last_heard_; }

void RemoteNode::dispatch(const CanFrame& f) {
  if (f.error || f.extended) {
    ++unknown_;
    return;
  }
  auto h = handlers_.find(f.id);
  if (h != handlers_.end()) {
    if (f.rtr) return;  // someone else requesting the same PDO: not data
    last_heard_ = nowS();
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
    last_heard_ = nowS();
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
    last_heard_ = nowS();
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

SdoResponse RemoteNode::sdoExchange(const CanFrame& request, uint16_t index, uint8_t subindex, double timeout_s) {
  const std::string what = "SDO " + hex(index) + "sub" + std::to_string(subindex) + " of node " + std::to_string(node_id_);
  sdo_response_.reset();
  if (!sendRaw(request)) throw SdoError(what + ": cannot send: " + last_error_);
  const bool got = waitFor(
      [&] { return sdo_response_ && sdo_response_->index == index && sdo_response_->subindex == subindex; }, timeout_s);
  if (!got) {
    ++sdo_timeouts_;
    throw SdoError(what + ": no answer within " + std::to_string(static_cast<int>(timeout_s * 1e3)) + " ms");
  }
  const SdoResponse r = *sdo_response_;
  sdo_response_.reset();
  if (r.kind == SdoResponse::Kind::kAbort) {
    ++sdo_aborts_;
    throw SdoError(what + " aborted: " + describeAbort(r.value), r.value);
  }
  if (r.kind == SdoResponse::Kind::kUnsupported) throw SdoError(what + ": segmented transfer not supported");
  return r;
}

uint32_t RemoteNode::sdoRead(uint16_t index, uint8_t subindex, double timeout_s) {
  const SdoResponse r = sdoExchange(encodeSdoRead(node_id_, index, subindex), index, subindex, timeout_s);
  if (r.kind != SdoResponse::Kind::kReadData)
    throw SdoError("SDO read " + hex(index) + "sub" + std::to_string(subindex) + ": node answered a write acknowledge");
  return r.value;
}

void RemoteNode::sdoWrite(uint16_t index, uint8_t subindex, uint32_t value, uint8_t size, double timeout_s) {
  const SdoResponse r = sdoExchange(encodeSdoWrite(node_id_, index, subindex, value, size), index, subindex, timeout_s);
  if (r.kind != SdoResponse::Kind::kWriteAck)
    throw SdoError("SDO write " + hex(index) + "sub" + std::to_string(subindex) + ": node answered read data");
}

}  // namespace canopen
}  // namespace hcl_drivers
