// libFuzzer target for the beacon parser (built with clang, run briefly by `make test`).
// Invariants checked on any input: no crash or sanitizer report; the same bytes give the
// same messages and counters whether fed at once or split; every message had its own '$'
// and line end in the input; garbage never exceeds the input.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "hcl_drivers/boards/beacon_protocol.h"

using namespace hcl_drivers::beacon_protocol;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t split = data[0] % (size + 1);
  Parser whole, parts;
  std::vector<Message> a, b;
  whole.feed(data, size, a);
  parts.feed(data, split, b);
  parts.feed(data + split, size - split, b);
  if (a.size() != b.size() || whole.stats().messages != a.size()) std::abort();
  const auto& s1 = whole.stats();
  const auto& s2 = parts.stats();
  if (s1.garbage_bytes != s2.garbage_bytes || s1.malformed != s2.malformed || s1.checksum_errors != s2.checksum_errors)
    std::abort();
  if (s1.garbage_bytes > size) std::abort();
  const std::string in(reinterpret_cast<const char*>(data), size);
  std::size_t dollars = 0, line_ends = 0;
  for (char c : in) {
    dollars += c == '$';
    line_ends += c == '\n';
  }
  if (a.size() > dollars || a.size() > line_ends) std::abort();
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].beacon_id != b[i].beacon_id || a[i].delta_us != b[i].delta_us) std::abort();
    if (a[i].beacon_id > 9 || a[i].delta_us > kMaxDeltaUs) std::abort();
  }
  return 0;
}
