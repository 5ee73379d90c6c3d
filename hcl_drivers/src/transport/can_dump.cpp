// can_dump: candump for our buses. Prints every frame of a CAN bus URL in candump's log format
// ("(seconds.micros) <bus> <ID>#<DATA>", RTR as "<ID>#R<len>"), so the same scripts read a
// socketcan:// bus and the CAN-over-UDP bus of the simulation.
//   can_dump <socketcan://IFACE | udp://127.0.0.1:PORT> [seconds]
#include <sys/time.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>

#include "hcl_drivers/transport/can_bus.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: can_dump <socketcan://IFACE | udp://127.0.0.1:PORT> [seconds]\n";
    return 2;
  }
  const double seconds = argc > 2 ? std::atof(argv[2]) : 0.0;
  try {
    auto bus = hcl_drivers::transport::openCanBus(argv[1]);
    auto ch = bus->open({});
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    hcl_drivers::transport::CanFrame f;
    while (seconds <= 0 || std::chrono::steady_clock::now() < end) {
      if (!ch->receive(f, 0.1)) continue;
      // The kernel's receive time (as candump's): this process's own scheduling stays out of it.
      double t = f.received;
      if (t <= 0.0) {
        timeval tv{};
        gettimeofday(&tv, nullptr);
        t = static_cast<double>(tv.tv_sec) + 1e-6 * static_cast<double>(tv.tv_usec);
      }
      std::string text = hcl_drivers::transport::toString(f);
      std::printf("(%.6f) %s %s\n", t, argv[1], text.c_str());
      std::fflush(stdout);  // a reader follows the bus live, not in 4 KB blocks
    }
    std::fflush(stdout);
  } catch (const std::exception& e) {
    std::cerr << "can_dump: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
