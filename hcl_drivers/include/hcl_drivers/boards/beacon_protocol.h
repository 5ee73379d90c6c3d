// The beacon receiver's serial messages (RS-232, default 9600 8N1), one per beacon pulse:
//
//   $B<id>,<delta_us>*<cs>\r\n        e.g.  $B1,4711*5C\r\n
//
//   id        one decimal digit, the beacon (0..9; Eurobot tables use 0..2)
//   delta_us  1..6 decimal digits: time from the beacon's radio sync to its ultrasonic
//             pulse, in microseconds (time of flight, raw; HAL turns it into a distance)
//   cs        two hex digits (either case): XOR of every byte between '$' and '*'
//   "\r\n"    terminator ("\n" alone is accepted)
// NMEA-like on purpose: readable in a terminal, and '$' is a sync byte that never occurs
// inside a message, so the parser resynchronises on the next '$' after garbage or a
// message cut short. Longest message: 17 bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace hcl_drivers {
namespace beacon_protocol {

constexpr std::size_t kMaxMessage = 17;  // "$B9,999999*FF\r\n" is 15; slack for nothing else
constexpr uint32_t kMaxDeltaUs = 999999;

struct Message {
  uint8_t beacon_id = 0;
  uint32_t delta_us = 0;
};

struct Stats {
  unsigned long messages = 0;         // valid messages
  unsigned long garbage_bytes = 0;    // bytes outside any message (line ends between messages excepted)
  unsigned long checksum_errors = 0;  // well-formed messages with a wrong checksum
  unsigned long malformed = 0;        // bad syntax, too long, or cut short by the next '$'
};

// The wire form of a message (used by tests; the emulator has its own encoder).
std::string encode(const Message& m);

// A byte-stream parser: feed whatever read() returned; complete valid messages come out.
class Parser {
 public:
  // Appends every valid message completed by these bytes to `out`, in order.
  void feed(const uint8_t* data, std::size_t n, std::vector<Message>& out);
  const Stats& stats() const { return stats_; }

 private:
  void finishFrame(std::vector<Message>& out);
  bool in_frame_ = false;
  std::string frame_;  // bytes after '$', up to '\n'
  Stats stats_;
};

}  // namespace beacon_protocol
}  // namespace hcl_drivers
