#include "hcl_drivers/boards/beacon_protocol.h"

#include <cstdio>

namespace hcl_drivers {
namespace beacon_protocol {

namespace {
int hexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}
}  // namespace

std::string encode(const Message& m) {
  char body[16];
  std::snprintf(body, sizeof(body), "B%u,%u", static_cast<unsigned>(m.beacon_id % 10),
                static_cast<unsigned>(m.delta_us > kMaxDeltaUs ? kMaxDeltaUs : m.delta_us));
  uint8_t cs = 0;
  for (const char* p = body; *p; ++p) cs ^= static_cast<uint8_t>(*p);
  char out[24];
  std::snprintf(out, sizeof(out), "$%s*%02X\r\n", body, cs);
  return out;
}

void Parser::feed(const uint8_t* data, std::size_t n, std::vector<Message>& out) {
  for (std::size_t i = 0; i < n; ++i) {
    const char c = static_cast<char>(data[i]);
    if (c == '$') {
      if (in_frame_) ++stats_.malformed;  // the previous message was cut short
      in_frame_ = true;
      frame_.clear();
      continue;
    }
    if (!in_frame_) {
      if (c != '\r' && c != '\n') ++stats_.garbage_bytes;
      continue;
    }
    if (c == '\n') {
      finishFrame(out);
      continue;
    }
    frame_.push_back(c);
    if (frame_.size() > kMaxMessage) {  // no terminator in sight: drop it, wait for the next '$'
      ++stats_.malformed;
      in_frame_ = false;
      frame_.clear();
    }
  }
}

// frame_ holds "B<id>,<digits>*<h><h>" plus an optional '\r'.
void Parser::finishFrame(std::vector<Message>& out) {
  in_frame_ = false;
  std::string f;
  f.swap(frame_);
  if (!f.empty() && f.back() == '\r') f.pop_back();
  const auto star = f.find('*');
  // Shortest: "B0,0*00" (7 bytes).
  if (f.size() < 7 || star == std::string::npos || star + 3 != f.size() || f[0] != 'B' || f[1] < '0' || f[1] > '9' ||
      f[2] != ',' || star < 4 || star - 3 > 6) {
    ++stats_.malformed;
    return;
  }
  uint32_t delta = 0;
  for (std::size_t i = 3; i < star; ++i) {
    if (f[i] < '0' || f[i] > '9') {
      ++stats_.malformed;
      return;
    }
    delta = delta * 10 + static_cast<uint32_t>(f[i] - '0');
  }
  const int hi = hexValue(f[star + 1]), lo = hexValue(f[star + 2]);
  if (hi < 0 || lo < 0) {
    ++stats_.malformed;
    return;
  }
  uint8_t cs = 0;
  for (std::size_t i = 0; i < star; ++i) cs ^= static_cast<uint8_t>(f[i]);
  if (cs != ((hi << 4) | lo)) {
    ++stats_.checksum_errors;
    return;
  }
  ++stats_.messages;
  out.push_back(Message{static_cast<uint8_t>(f[1] - '0'), delta});
}

}  // namespace beacon_protocol
}  // namespace hcl_drivers
