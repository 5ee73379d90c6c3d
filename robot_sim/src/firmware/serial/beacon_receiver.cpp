// Emulator of the beacon receiver on RS-232: creates a pty (posix_openpt), links its slave
// side at ~port for the driver to open with termios, and writes what the real receiver
// sends, one line per beacon pulse:  $B<id>,<delta_us>*<XOR of the bytes between $ and *, 2 hex>\r\n
// (format: hcl_drivers/boards/beacon_protocol.h; this encoder is written independently).
//
// Parameters: robot_sim/PARAMETERS.md (BeaconReceiver). Without a world: one message every
// period, ids 0, 1, 2 in turn, delta_us = base_delta_us[id] + (sequence number % 1000). With a
// world: sends World::takeBeaconMeasurements(), polled every 5 ms.
// Truth (tests/bench only): /sim/<name>/sent (std_msgs/Float64MultiArray per valid message:
// [beacon_id, delta_us, sequence, wall time just before the message was written [s]]),
// /sim/<name>/injected (std_msgs/UInt32MultiArray: [garbage bytes, truncated messages], latched).
// Faults: "board_silent" (nothing sent), "serial_garbage", "serial_truncate" (while active,
// garbage after / truncation of every message).
#include <fcntl.h>
#include <std_msgs/Float64MultiArray.h>
#include <std_msgs/UInt32MultiArray.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <thread>

#include "robot_sim/firmware/firmware_registry.h"
#include "robot_sim/world/world.h"
#include <robot_core/realtime.h>

namespace robot_sim {

class BeaconReceiverFirmware : public Firmware {
 public:
  ~BeaconReceiverFirmware() override { stop(); }

  void configure(const robot_core::Params& params) override {
    params.describe("port", "the pty link to create, an absolute path: the driver's port in simulation");
    port_ = params.requireString("port");
    if (port_.empty() || port_[0] != '/') params.check("port", "must be an absolute path for the pty link");
    params.describe("period", "[s] without a world: one message every period");
    period_ = params.optionalDouble("period", 0.05);
    params.requirePositive("period", period_);
    params.describe("base_delta_us", "[us] without a world: each beacon's base time of flight (default [3000, 4500, 6000])");
    base_.clear();
    std::vector<double> deltas = params.optionalDoubleList("base_delta_us", 1);
    if (deltas.empty()) deltas = {3000, 4500, 6000};
    for (double us : deltas) base_.push_back(static_cast<int>(us));
    params.describe("garbage_every", "random garbage bytes (never '$') after every Nth message; 0 never");
    garbage_every_ = params.optionalInt("garbage_every", 0);
    params.requireInRange("garbage_every", garbage_every_, 0, std::numeric_limits<double>::infinity());
    params.describe("truncate_every", "cut every Nth message short (not counted as sent); 0 never");
    truncate_every_ = params.optionalInt("truncate_every", 0);
    params.requireInRange("truncate_every", truncate_every_, 0, std::numeric_limits<double>::infinity());
    params.describe("seed", "the seed of the garbage bytes");
    rng_.seed(static_cast<unsigned>(params.optionalInt("seed", 1)));
  }

  // The pty link is made (and removed by stop()) only here: a checker that only configured an
  // emulator never touches the running simulation's link.
  void start(FirmwareContext& ctx) override {
    world_ = ctx.world;
    link_ = port_;

    master_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (master_ < 0 || ::grantpt(master_) != 0 || ::unlockpt(master_) != 0)
      throw std::runtime_error(std::string("cannot create a pty: ") + std::strerror(errno));
    const char* slave = ::ptsname(master_);
    // Raw line discipline on the slave, so the driver sees exactly these bytes even before it
    // configures the port itself; keeping a slave fd open keeps the pty alive between openers.
    slave_ = ::open(slave, O_RDWR | O_NOCTTY | O_CLOEXEC);
    termios tio{};
    if (slave_ >= 0 && ::tcgetattr(slave_, &tio) == 0) {
      ::cfmakeraw(&tio);
      ::tcsetattr(slave_, TCSANOW, &tio);
    }
    for (std::size_t i = 1; i < link_.size(); ++i)
      if (link_[i] == '/') ::mkdir(link_.substr(0, i).c_str(), 0777);
    ::unlink(link_.c_str());
    if (::symlink(slave, link_.c_str()) != 0)
      throw std::runtime_error("cannot link " + link_ + " -> " + slave + ": " + std::strerror(errno));
    ::fcntl(master_, F_SETFL, ::fcntl(master_, F_GETFL) | O_NONBLOCK);

    sent_pub_ = ctx.nh.advertise<std_msgs::Float64MultiArray>("/sim/" + ctx.name + "/sent", 1000);
    injected_pub_ = ctx.nh.advertise<std_msgs::UInt32MultiArray>("/sim/" + ctx.name + "/injected", 1, true);
    running_ = true;
    thread_ = std::thread([this] { run(); });
  }

  void stop() override {
    running_ = false;
    if (thread_.joinable()) thread_.join();
    if (!link_.empty()) ::unlink(link_.c_str());
    if (slave_ >= 0) ::close(slave_);
    if (master_ >= 0) ::close(master_);
    slave_ = master_ = -1;
  }

  bool applyFault(const std::string& kind, bool active) override {
    if (kind == "serial_garbage") fault_garbage_ = active;
    else if (kind == "serial_truncate") fault_truncate_ = active;
    else if (kind == "board_silent") setSilent(active);
    else return false;
    return true;
  }

 private:
  static std::string line(int id, uint32_t delta) {
    char body[24];
    std::snprintf(body, sizeof(body), "B%d,%u", id, delta);
    unsigned cs = 0;
    for (const char* p = body; *p; ++p) cs ^= static_cast<unsigned char>(*p);
    char out[40];
    std::snprintf(out, sizeof(out), "$%s*%02X\r\n", body, cs);
    return out;
  }

  void run() {
    robot_core::enterRealtime("the beacon receiver emulator");
    auto next = std::chrono::steady_clock::now();
    uint32_t seq = 0;
    while (running_) {
      // The driver's writes (if any) and echo: read and ignore, so the pty never fills up.
      uint8_t sink[256];
      while (::read(master_, sink, sizeof(sink)) > 0) {
      }
      if (world_) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        for (const auto& m : world_->takeBeaconMeasurements())
          send(m.beacon_id, static_cast<uint32_t>(std::lround(m.delta_s * 1e6)), seq++);
        continue;
      }
      next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(period_));
      std::this_thread::sleep_until(next);
      const int id = static_cast<int>(seq % 3);
      send(id, static_cast<uint32_t>(base_[id % base_.size()] + seq % 1000), seq);
      ++seq;
    }
  }

  void send(int id, uint32_t delta, uint32_t seq) {
    if (silent()) return;
    std::string out = line(id % 10, std::min<uint32_t>(delta, 999999));
    ++count_;
    const bool truncate = fault_truncate_ || (truncate_every_ > 0 && count_ % truncate_every_ == 0);
    if (truncate) {
      out.resize(1 + rng_() % (out.size() - 3));  // keep '$' and lose at least the terminator
      ++truncated_;
    }
    const bool garbage = fault_garbage_ || (garbage_every_ > 0 && count_ % garbage_every_ == 0);
    std::string junk;
    if (garbage) {
      const int n = 1 + static_cast<int>(rng_() % 12);
      for (int i = 0; i < n; ++i) {
        char c;
        do c = static_cast<char>(rng_() & 0xFF);
        while (c == '$');
        junk.push_back(c);
      }
      garbage_bytes_ += static_cast<uint32_t>(junk.size());
    }
    // Taken just before the write: the reader may see the bytes before write() even returns.
    const double t_last = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    write(out);
    if (!truncate) {
      std_msgs::Float64MultiArray s;
      s.data = {static_cast<double>(id), static_cast<double>(delta), static_cast<double>(seq), t_last};
      sent_pub_.publish(s);
    }
    if (!junk.empty()) write(junk);
    if (truncate || garbage) {
      std_msgs::UInt32MultiArray inj;
      inj.data = {garbage_bytes_, truncated_};
      injected_pub_.publish(inj);
    }
  }

  // Whole or nothing: a full pty buffer (nobody reading) drops the bytes, like a line with no listener.
  void write(const std::string& bytes) {
    std::size_t at = 0;
    int tries = 0;
    while (at < bytes.size() && tries++ < 50) {
      const ssize_t n = ::write(master_, bytes.data() + at, bytes.size() - at);
      if (n > 0) at += static_cast<std::size_t>(n);
      else if (errno == EAGAIN) std::this_thread::sleep_for(std::chrono::microseconds(200));
      else break;
    }
  }

  World* world_ = nullptr;
  std::string port_, link_;  // configured; link_ once started
  double period_ = 0.05;
  std::vector<int> base_;
  int garbage_every_ = 0, truncate_every_ = 0;
  std::mt19937 rng_;
  int master_ = -1, slave_ = -1;
  std::atomic<bool> running_{false}, fault_garbage_{false}, fault_truncate_{false};
  uint32_t count_ = 0, garbage_bytes_ = 0, truncated_ = 0;
  std::thread thread_;
  ros::Publisher sent_pub_, injected_pub_;
};

ROBOT_SIM_REGISTER_FIRMWARE("BeaconReceiver", BeaconReceiverFirmware);

}  // namespace robot_sim
