// Emulator of the skeleton's example board: a UDP server answering the exchange request
// (request 'E' 'X' 0x01 seq lamp -> reply 'E' 'X' 0x81 seq dial_lo dial_hi lamp uptime[4], LE).
// The dial turns by itself as a triangle wave so something always moves.
//
// Parameters: robot_sim/PARAMETERS.md (ExampleBoard).
// Truth: /sim/<name>/firmware (robot_sim/ExampleFirmware) at 50 Hz.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <robot_sim/ExampleFirmware.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "robot_sim/firmware/firmware_registry.h"
#include <robot_core/realtime.h>

namespace robot_sim {

class ExampleBoardFirmware : public Firmware {
 public:
  ~ExampleBoardFirmware() override { stop(); }

  // Every parameter into members (check_config runs this alone); start() opens the socket.
  void configure(const robot_core::Params& params) override {
    params.describe("endpoint", "udp://HOST:PORT to listen on (the driver's endpoint in simulation)");
    endpoint_ = params.requireString("endpoint");
    const auto colon = endpoint_.rfind(':');
    const int port = colon == std::string::npos ? 0 : std::atoi(endpoint_.c_str() + colon + 1);
    if (endpoint_.rfind("udp://", 0) != 0 || colon < 6 || port < 1 || port > 65535)
      params.check("endpoint", "must be udp://HOST:PORT (PORT 1..65535)");
    params.describe("dial_period", "[s] the dial's triangle wave period");
    dial_period_ = params.optionalDouble("dial_period", 8.0);
    params.requirePositive("dial_period", dial_period_);
  }

  void start(FirmwareContext& ctx) override {
    const std::string& url = endpoint_;
    const std::string hostport = url.substr(6);
    const auto colon = hostport.rfind(':');
    const int port = std::atoi(hostport.substr(colon + 1).c_str());
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    int one = 1;
    ::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(port));
    ::inet_pton(AF_INET, hostport.substr(0, colon).c_str(), &addr.sin_addr);
    if (::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0)
      throw std::runtime_error("cannot listen on " + url + ": " + std::strerror(errno));

    truth_pub_ = ctx.nh.advertise<ExampleFirmware>("/sim/" + ctx.name + "/firmware", 10);
    truth_timer_ = ctx.nh.createTimer(ros::Duration(0.02), [this](const ros::TimerEvent&) { publishTruth(); });
    boot_ = std::chrono::steady_clock::now();
    running_ = true;
    thread_ = std::thread([this] { serve(); });
  }

  void stop() override {
    running_ = false;
    if (thread_.joinable()) thread_.join();
    truth_timer_.stop();
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  // The firmware's ADC: a triangle wave over simulated (or wall) time.
  uint16_t dial() const {
    const double phase = std::fmod(ros::Time::now().toSec(), dial_period_) / dial_period_;
    const double tri = phase < 0.5 ? 2.0 * phase : 2.0 - 2.0 * phase;
    return static_cast<uint16_t>(std::lround(1023.0 * tri));
  }

  void serve() {
    robot_core::enterRealtime("the example board emulator");
    uint8_t in[64];
    while (running_) {
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, 50) <= 0) continue;
      sockaddr_in from{};
      socklen_t from_len = sizeof(from);
      const ssize_t n = ::recvfrom(fd_, in, sizeof(in), 0, reinterpret_cast<sockaddr*>(&from), &from_len);
      if (n < 0) continue;
      if (n != 5 || in[0] != 'E' || in[1] != 'X' || in[2] != 0x01) {
        ++malformed_;
        continue;
      }
      if (silent()) continue;
      const uint16_t d = dial();
      const uint32_t up = static_cast<uint32_t>(
          std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - boot_).count());
      lamp_ = in[4];
      dial_ = d;
      const uint8_t out[11] = {'E', 'X', 0x81, in[3], static_cast<uint8_t>(d & 0xFF), static_cast<uint8_t>(d >> 8), in[4],
                               static_cast<uint8_t>(up), static_cast<uint8_t>(up >> 8), static_cast<uint8_t>(up >> 16),
                               static_cast<uint8_t>(up >> 24)};
      ::sendto(fd_, out, sizeof(out), 0, reinterpret_cast<sockaddr*>(&from), from_len);
      ++requests_;
    }
  }

  void publishTruth() {
    ExampleFirmware m;
    m.header.stamp = ros::Time::now();
    m.dial_raw = dial();
    m.lamp_pwm = lamp_;
    m.requests = requests_;
    m.malformed = malformed_;
    m.silent = silent();
    truth_pub_.publish(m);
  }

  int fd_ = -1;
  std::string endpoint_;
  double dial_period_ = 8.0;
  std::chrono::steady_clock::time_point boot_;
  std::atomic<bool> running_{false};
  std::atomic<uint8_t> lamp_{0};
  std::atomic<uint16_t> dial_{0};
  std::atomic<uint32_t> requests_{0};
  std::atomic<uint32_t> malformed_{0};
  std::thread thread_;
  ros::Publisher truth_pub_;
  ros::Timer truth_timer_;
};

ROBOT_SIM_REGISTER_FIRMWARE("ExampleBoard", ExampleBoardFirmware);

}  // namespace robot_sim
