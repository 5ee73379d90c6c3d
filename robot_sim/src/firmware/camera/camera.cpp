// Emulator of a camera: renders the world (scene_renderer.h) and serves it as an MJPEG
// stream over HTTP (multipart/x-mixed-replace, what IP webcams serve), so the driver's
// OpenCV VideoCapture opens it exactly like a camera: device "http://127.0.0.1:PORT/camera.mjpg".
// A V4L2 device cannot be emulated without a kernel module (v4l2loopback); the stream is
// the closest VideoCapture path, and the driver code above VideoCapture is identical.
//
// Parameters: robot_sim/PARAMETERS.md (Camera).
// Without a world it renders an empty table with the robot at its start (0.25, 0.25).
// Truth (tests only): /sim/<name>/frames (std_msgs/UInt32, frames served, latched).
// Faults: "board_silent" (the stream stalls: no frames).
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <std_msgs/UInt32.h>
#include <sys/socket.h>
#include <unistd.h>

#include <opencv2/imgcodecs.hpp>

#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

#include "robot_sim/firmware/firmware_registry.h"
#include "scene_renderer.h"

namespace robot_sim {

class CameraFirmware : public Firmware {
 public:
  ~CameraFirmware() override { stop(); }

  void configure(const robot_core::Params& params) override {
    params.describe("port", "the TCP port on 127.0.0.1 it serves the MJPEG stream on (the driver's device in simulation)");
    port_ = params.requireInt("port");
    params.requireInRange("port", port_, 1, 65535);
    params.describe("fps", "[Hz, wall clock] frames served a second");
    fps_ = params.optionalDouble("fps", 10.0);
    params.requireInRange("fps", fps_, 1e-3, 60.0);
    params.describe("mount", "where the camera looks from: top (the whole table from above) or front (on the robot)");
    model_.mount = params.optionalString("mount", "top");
    params.requireOneOf("mount", model_.mount, {"top", "front"});
    params.describe("width", "[px] image width");
    model_.width = params.optionalInt("width", 320);
    params.requireInRange("width", model_.width, 16, 4096);
    params.describe("height", "[px] image height");
    model_.height = params.optionalInt("height", 240);
    params.requireInRange("height", model_.height, 16, 4096);
    params.describe("x", "[m] front mount: ahead of base_link");
    model_.x = params.optionalDouble("x", model_.x);
    params.describe("z", "[m] front mount: height above the table");
    model_.z = params.optionalDouble("z", model_.z);
    params.describe("pitch", "[rad] front mount: tilt down");
    model_.pitch = params.optionalDouble("pitch", model_.pitch);
    params.describe("hfov", "[rad] front mount: horizontal field of view");
    model_.hfov = params.optionalDouble("hfov", model_.hfov);
    params.describe("quality", "JPEG quality of each frame");
    quality_ = params.optionalInt("quality", 85);
    params.requireInRange("quality", quality_, 1, 100);
  }

  void start(FirmwareContext& ctx) override {
    world_ = ctx.world;
    const int port = port_;
    listen_fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    int one = 1;
    ::setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::bind(listen_fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0 || ::listen(listen_fd_, 4) != 0)
      throw std::runtime_error("cannot serve the camera on 127.0.0.1:" + std::to_string(port) + ": " + std::strerror(errno));
    frames_pub_ = ctx.nh.advertise<std_msgs::UInt32>("/sim/" + ctx.name + "/frames", 1, true);
    running_ = true;
    thread_ = std::thread([this] { run(); });
  }

  void stop() override {
    running_ = false;
    if (thread_.joinable()) thread_.join();
    for (int c : clients_) ::close(c);
    clients_.clear();
    if (listen_fd_ >= 0) ::close(listen_fd_);
    listen_fd_ = -1;
  }

 private:
  WorldSnapshot snapshot() const {
    if (world_) return world_->snapshot();
    WorldSnapshot s;
    s.robot = {0.25, 0.25, 0.0};
    s.robot_radius = 0.15;
    return s;
  }

  static bool sendAll(int fd, const void* data, std::size_t n) {
    const auto* p = static_cast<const uint8_t*>(data);
    while (n > 0) {
      pollfd w{fd, POLLOUT, 0};
      if (::poll(&w, 1, 200) <= 0) return false;  // a client that stopped reading is dropped
      const ssize_t k = ::send(fd, p, n, MSG_NOSIGNAL);
      if (k <= 0) return false;
      p += k;
      n -= static_cast<std::size_t>(k);
    }
    return true;
  }

  void accept() {
    pollfd p{listen_fd_, POLLIN, 0};
    while (::poll(&p, 1, 0) > 0) {
      const int c = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
      if (c < 0) return;
      char req[2048];
      pollfd r{c, POLLIN, 0};
      if (::poll(&r, 1, 500) > 0) (void)::recv(c, req, sizeof(req), 0);  // the GET; any path serves the stream
      static const char kHeader[] =
          "HTTP/1.0 200 OK\r\nServer: robot_sim camera\r\nCache-Control: no-cache\r\n"
          "Content-Type: multipart/x-mixed-replace; boundary=frame\r\n\r\n";
      if (sendAll(c, kHeader, sizeof(kHeader) - 1))
        clients_.push_back(c);
      else
        ::close(c);
    }
  }

  void run() {
    // Frames at fps_ on the camera's clock (firmwareNow: simulated time in a simulation), so the
    // vision sees as many frames per simulated second at any real-time factor.
    const double period = 1.0 / fps_;
    double next = firmwareNow();
    std::vector<uint8_t> jpg;
    uint32_t served = 0;
    while (running_) {
      next += period;
      for (double left = next - firmwareNow(); running_ && left > 0.0; left = next - firmwareNow())
        std::this_thread::sleep_for(std::chrono::duration<double>(firmwareWallSlice(left)));
      if (firmwareNow() - next > period) next = firmwareNow();  // fell behind: skip, never burst
      accept();
      if (clients_.empty() || silent()) continue;
      cv::imencode(".jpg", renderScene(snapshot(), model_), jpg, {cv::IMWRITE_JPEG_QUALITY, quality_});
      char part[128];
      const int n = std::snprintf(part, sizeof(part), "--frame\r\nContent-Type: image/jpeg\r\nContent-Length: %zu\r\n\r\n", jpg.size());
      for (auto it = clients_.begin(); it != clients_.end();) {
        if (sendAll(*it, part, static_cast<std::size_t>(n)) && sendAll(*it, jpg.data(), jpg.size()) && sendAll(*it, "\r\n", 2)) {
          ++it;
        } else {
          ::close(*it);
          it = clients_.erase(it);
        }
      }
      std_msgs::UInt32 m;
      m.data = ++served;
      frames_pub_.publish(m);
    }
  }

  World* world_ = nullptr;
  CameraModel model_;
  double fps_ = 10.0;
  int quality_ = 85;
  int listen_fd_ = -1;
  int port_ = 0;
  std::vector<int> clients_;  // server thread only
  std::atomic<bool> running_{false};
  std::thread thread_;
  ros::Publisher frames_pub_;
};

ROBOT_SIM_REGISTER_FIRMWARE("Camera", CameraFirmware);

}  // namespace robot_sim
