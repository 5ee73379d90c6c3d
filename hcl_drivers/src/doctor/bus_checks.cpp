#include "bus_checks.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <regex>
#include <set>
#include <thread>

#include "hcl_drivers/canopen/canopen.h"
#include "hcl_drivers/transport/endpoint.h"
#include "hcl_drivers/transport/i2c_bus.h"

namespace hcl_drivers {
namespace doctor {

namespace {

std::string run(const std::string& command) {
  std::string out;
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  if (!pipe) return out;
  char buf[512];
  while (fgets(buf, sizeof buf, pipe.get())) out += buf;
  return out;
}

std::string hex2(int v) {
  char b[8];
  std::snprintf(b, sizeof b, "0x%02x", v);
  return b;
}

// Moves a missing board's FAIL row to the finding "found at N, expected M".
void nameWrongAddress(CheckReport& board, int found, const std::string& (*unit)(int), const std::string& param,
                      const std::string& fix) {
  for (auto& row : board.rows())
    if (row.level == CheckLevel::kFail) {
      const std::string expected = unit(board.channel.address), at = unit(found);
      row.found = "found at " + at + ", expected " + expected;
      row.hint = board.board() + " answers at " + at + ": set `" + param + ": " + at + "` or " + fix;
    }
}

const std::string& decimal(int v) {
  static thread_local std::string s;
  s = std::to_string(v);
  return s;
}
const std::string& hexAddress(int v) {
  static thread_local std::string s;
  s = hex2(v);
  return s;
}

// computer/can/<iface>/bitrate, 0 when not configured.
int configuredBitrate(const std::string& iface, XmlRpc::XmlRpcValue& computer) {
  using V = XmlRpc::XmlRpcValue;
  if (computer.getType() != V::TypeStruct || !computer.hasMember("can")) return 0;
  V& can = computer["can"];
  if (can.getType() != V::TypeStruct || !can.hasMember(iface) || can[iface].getType() != V::TypeStruct ||
      !can[iface].hasMember("bitrate") || can[iface]["bitrate"].getType() != V::TypeInt)
    return 0;
  return static_cast<int>(can[iface]["bitrate"]);
}

// The interface row of socketcan://IFACE, from `ip -details -statistics link show`.
void checkInterface(const std::string& iface, XmlRpc::XmlRpcValue& computer, std::vector<CheckRow>& rows) {
  const int want = configuredBitrate(iface, computer);
  const std::string expected = "up" + (want ? ", " + std::to_string(want) + " bit/s" : std::string());
  const std::string board = "bus " + iface;
  const std::string out = run("ip -details -statistics link show " + iface + " 2>&1");
  const std::string up_cmd = "sudo ip link set " + iface + " down; sudo ip link set " + iface + " type can bitrate " +
                             (want ? std::to_string(want) : std::string("BITRATE")) + "; sudo ip link set " + iface + " up";
  if (out.find("link/can") == std::string::npos) {
    rows.push_back({board, "interface", expected, out.empty() ? "no such interface" : "no CAN interface: " + out.substr(0, out.find('\n')),
                    CheckLevel::kFail, "plug in the CAN adapter (ip link); make install-robot brings " + iface + " up at boot"});
    return;
  }
  std::smatch m;
  const bool is_up = std::regex_search(out, m, std::regex("<[^>]*\\bUP\\b[^>]*>"));
  const bool is_virtual = out.find("vcan") != std::string::npos;
  int bitrate = 0;
  if (std::regex_search(out, m, std::regex("bitrate (\\d+)"))) bitrate = std::atoi(m[1].str().c_str());
  std::string state = "ERROR-ACTIVE";
  if (std::regex_search(out, m, std::regex("can state ([A-Z-]+)"))) state = m[1];
  std::string counters;
  if (std::regex_search(out, m, std::regex("berr-counter tx (\\d+) rx (\\d+)")))
    counters = ", error counters tx " + m[1].str() + " rx " + m[2].str();
  std::string found = is_up ? "up" : "down";
  if (is_virtual) found += ", virtual (vcan: no bitrate)";
  else found += ", " + std::to_string(bitrate) + " bit/s, " + state + counters;
  if (!is_up)
    rows.push_back({board, "interface", expected, found, CheckLevel::kFail, up_cmd});
  else if (!is_virtual && want && bitrate != want)
    rows.push_back({board, "interface", expected, found, CheckLevel::kFail, "wrong bitrate: " + up_cmd});
  else if (!is_virtual && state == "BUS-OFF")
    rows.push_back({board, "interface", expected, found, CheckLevel::kFail,
                    "bus-off: termination (120 ohm at both ends), CAN_H/CAN_L swapped, a board at another bitrate"});
  else if (!is_virtual && state != "ERROR-ACTIVE")
    rows.push_back({board, "interface", expected, found, CheckLevel::kWarn,
                    "errors on the bus: termination, wiring, a board at another bitrate"});
  else
    rows.push_back({board, "interface", expected, found, CheckLevel::kOk, ""});
}

}  // namespace

int pairMissing(const std::string& board, int expected, const std::vector<std::pair<int, std::string>>& found) {
  int best = -1;
  for (const auto& f : found) {
    if (best < 0) {
      best = f.first;
      continue;
    }
    const bool named = f.second.find(board) != std::string::npos;
    const bool best_named = std::any_of(found.begin(), found.end(), [&](const auto& g) {
      return g.first == best && g.second.find(board) != std::string::npos;
    });
    if ((named && !best_named) || (named == best_named && std::abs(f.first - expected) < std::abs(best - expected)))
      best = f.first;
  }
  return best;
}

void checkCanBus(const std::string& url, const std::vector<CheckReport*>& boards, XmlRpc::XmlRpcValue& computer,
                 double window, std::vector<CheckRow>& rows) {
  const auto ep = transport::parseEndpoint(url);
  if (ep.scheme == "socketcan") checkInterface(ep.host, computer, rows);
  const std::string board = "bus " + (ep.scheme == "socketcan" ? ep.host : url);
  std::shared_ptr<transport::CanBus> bus;
  try {
    bus = transport::openCanBus(url);
  } catch (const std::exception& e) {
    return;  // each board already said why
  }
  // Scan: an SDO read of 0x1000 to every node id nobody configured, paced so a real
  // controller's transmit queue never overflows; SDO answers and heartbeats collected.
  std::set<int> configured;
  for (auto* b : boards) configured.insert(b->channel.address);
  auto channel = bus->open({transport::CanFilter{0x580, 0x780, false}, transport::CanFilter{0x700, 0x780, false}});
  std::set<int> answered;
  auto collect = [&](double seconds) {
    transport::CanFrame f;
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < until)
      if (channel->receive(f, 0.01) && !f.rtr) {
        const int id = static_cast<int>(f.id & 0x7F);
        if (!configured.count(id)) answered.insert(id);
      }
  };
  for (int id = 1; id <= 127; ++id) {
    if (configured.count(id)) continue;
    const auto request = canopen::encodeSdoRead(static_cast<uint8_t>(id), 0x1000, 0);
    for (int attempt = 0; attempt < 5 && !channel->send(request); ++attempt)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    collect(0.001);
  }
  collect(0.3);
  std::vector<std::pair<int, std::string>> found;
  for (int id : answered) {
    std::string name;
    try {
      canopen::RemoteNode node(bus, static_cast<uint8_t>(id));
      const auto bytes = node.sdoUpload(canopen::kDeviceNameIndex, 0, 0.1);
      name = std::string(bytes.begin(), bytes.end());
    } catch (const std::exception&) {
    }
    found.emplace_back(id, name);
  }
  for (auto* b : boards) {
    if (b->channel.answered) continue;
    const int at = pairMissing(b->board(), b->channel.address, found);
    if (at < 0) continue;
    nameWrongAddress(*b, at, decimal, "node_id", "the board's DIP switches");
    found.erase(std::remove_if(found.begin(), found.end(), [at](const auto& f) { return f.first == at; }), found.end());
  }
  for (const auto& f : found)
    rows.push_back({board, "unconfigured node", "none", "node " + std::to_string(f.first) + (f.second.empty() ? "" : " ('" + f.second + "')"),
                    CheckLevel::kWarn, "a board nobody configured answers: add its block to the config, or take it off the bus"});

  // Load and errors over the window: every frame on the bus, bits as on the wire (standard
  // frame: 47 bits + 8 per data byte, plus ~15 % stuffing).
  auto all = bus->open({});
  const auto before = bus->status();
  unsigned long frames = 0;
  double bits = 0.0;
  transport::CanFrame f;
  const auto t0 = std::chrono::steady_clock::now();
  const auto until = t0 + std::chrono::duration<double>(window);
  while (std::chrono::steady_clock::now() < until)
    if (all->receive(f, 0.05)) {
      ++frames;
      bits += 1.15 * (47 + 8 * (f.rtr ? 0 : f.dlc));
    }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto after = bus->status();
  const unsigned long errors = after.error_frames - before.error_frames;
  int bitrate = 0;
  if (ep.scheme == "socketcan") bitrate = configuredBitrate(ep.host, computer);
  char text[160];
  if (bitrate)
    std::snprintf(text, sizeof text, "%.0f frames/s, load %.1f %% of %d bit/s, %lu error frames in %.1f s", frames / seconds,
                  100.0 * bits / seconds / bitrate, bitrate, errors, seconds);
  else
    std::snprintf(text, sizeof text, "%.0f frames/s (%.0f bit/s), %lu error frames in %.1f s", frames / seconds, bits / seconds,
                  errors, seconds);
  const bool busy = bitrate && bits / seconds > 0.5 * bitrate;
  if (errors)
    rows.push_back({board, "load and errors", "no error frames", text, CheckLevel::kWarn,
                    "error frames: termination, wiring, a node at another bitrate"});
  else if (busy)
    rows.push_back({board, "load and errors", "load below 50 %", text, CheckLevel::kWarn,
                    "a busy bus before the product runs: a node streaming PDOs, or a higher bitrate needed"});
  else
    rows.push_back({board, "load and errors", "no error frames", text, CheckLevel::kOk, ""});
}

void checkI2cBus(const std::string& url, const std::vector<CheckReport*>& boards, std::vector<CheckRow>& rows) {
  std::shared_ptr<transport::I2cBus> bus;
  try {
    bus = transport::openI2cBus(url);
  } catch (const std::exception&) {
    return;  // each board already said why
  }
  std::set<int> configured;
  bool any_missing = false;
  for (auto* b : boards) {
    configured.insert(b->channel.address);
    any_missing |= !b->channel.answered;
  }
  // Like `i2cdetect -r`: a one-byte read from every address nobody configured.
  bus->setRetries(0);
  std::vector<std::pair<int, std::string>> found;
  for (int address = 0x03; address <= 0x7F; ++address) {
    if (configured.count(address)) continue;
    std::vector<transport::I2cMessage> msgs{{static_cast<uint8_t>(address), true, std::vector<uint8_t>(1)}};
    std::string error;
    if (bus->transfer(msgs, error) == transport::I2cStatus::kOk) found.emplace_back(address, "");
  }
  for (auto* b : boards) {
    if (b->channel.answered || !any_missing) continue;
    const int at = pairMissing(b->board(), b->channel.address, found);
    if (at < 0) continue;
    nameWrongAddress(*b, at, hexAddress, "address", "the chip's address pins / its programmed address");
    found.erase(std::remove_if(found.begin(), found.end(), [at](const auto& f) { return f.first == at; }), found.end());
  }
  for (const auto& f : found)
    rows.push_back({"bus " + url, "unconfigured chip", "none", "a chip ACKs at " + hex2(f.first), CheckLevel::kWarn,
                    "a chip nobody configured: add its block to the config, or check its address"});
}

}  // namespace doctor
}  // namespace hcl_drivers
