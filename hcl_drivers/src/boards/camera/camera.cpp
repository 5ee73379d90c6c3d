// A camera (USB webcam on V4L2, or any source OpenCV's VideoCapture opens; see
// transport/camera_source.h). A grabber thread reads frames as the camera delivers them and
// keeps only the newest (a camera is a stream: reading at our rate would queue old frames);
// service() publishes the newest frame at ~rate if it is new. A camera that stops
// delivering is released and reopened every ~reopen_period.
//
// Parameters (besides rate/loop): read and described in configure() (the table:
// hcl_drivers/PARAMETERS.md, make docs).
// Topics: ~image (sensor_msgs/Image, bgr8), ~state (hcl_drivers/CameraState, latched).
#include <hcl_drivers/CameraState.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <mutex>

#include <robot_core/priority_inheritance_mutex.h>
#include <thread>

#include "hcl_drivers/board_nodelet.h"
#include "hcl_drivers/transport/camera_source.h"

namespace hcl_drivers {

class Camera : public Board {
 public:
  ~Camera() override {
    running_ = false;
    if (grabber_.joinable()) grabber_.join();
  }

  void configure(const robot_core::Params& p) override {
    p.describe("device", "\"0\" / \"/dev/video0\" (V4L2) or a URL (simulation: http://127.0.0.1:PORT/camera.mjpg)");
    device_ = p.requireString("device");
    p.describe("width", "[px] requested image width for V4L2; 0 = the device's default");
    width_ = p.optionalInt("width", 0);
    p.requireInRange("width", width_, 0, 8192);
    p.describe("height", "[px] requested image height for V4L2; 0 = the device's default");
    height_ = p.optionalInt("height", 0);
    p.requireInRange("height", height_, 0, 8192);
    p.describe("fps", "[Hz] requested frame rate for V4L2; 0 = the device's default");
    fps_ = p.optionalDouble("fps", 0.0);
    p.requireInRange("fps", fps_, 0.0, 240.0);
    p.describe("reopen_period", "[s] a camera that cannot be opened or stops delivering is released and reopened this often");
    reopen_period_ = p.optionalDouble("reopen_period", 1.0);
    p.requirePositive("reopen_period", reopen_period_);
    p.describe("frame_id", "frame of the images: the REP-103 optical frame from the URDF; when absent <board name>_optical_frame");
    frame_id_ = p.optionalString("frame_id", p.ns().substr(p.ns().rfind('/') + 1) + "_optical_frame");
    p.describe("check_window", "[s] how long the hardware doctor watches the frames (their size and rate)");
    check_window_ = p.optionalDouble("check_window", 2.0);  // the doctor's
  }

  void init(BoardContext& ctx) override {
    stale_after_ = std::max(1.0, 3.0 / ctx.rate);
    source_ = std::make_unique<transport::CameraSource>(device_, width_, height_, fps_);
    image_pub_ = ctx.pnh.advertise<sensor_msgs::Image>("image", 2);
    state_pub_ = ctx.pnh.advertise<CameraState>("state", 1, true);
    running_ = true;
    grabber_ = std::thread([this] { grab(); });
  }

  // The doctor: the camera opens and delivers frames for ~check_window seconds:
  // their size and rate against ~width/~height/~fps.
  void check(BoardContext& /*ctx*/, CheckReport& report) override {
    const std::string& device = device_;
    const int width = width_, height = height_;
    const double fps = fps_;
    const double window = check_window_;
    transport::CameraSource source(device, width, height, fps);
    std::string error;
    if (!source.open(error)) {
      report.fail("device", device, error, "is the camera plugged in (v4l2-ctl --list-devices)?");
      return;
    }
    cv::Mat frame;
    int frames = 0, w = 0, h = 0;
    const auto t0 = std::chrono::steady_clock::now();
    const auto until = t0 + std::chrono::duration<double>(window);
    while (std::chrono::steady_clock::now() < until && source.read(frame)) {
      if (frame.empty()) continue;
      ++frames;
      w = frame.cols;
      h = frame.rows;
    }
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    char expected[64], found[96];
    std::snprintf(expected, sizeof expected, "%dx%d at %.0f fps", width, height, fps);
    std::snprintf(found, sizeof found, "%dx%d at %.1f fps (%d frames in %.1f s)", w, h, frames / std::max(elapsed, 1e-3), frames, elapsed);
    if (frames == 0)
      report.fail("frames", expected, "opened, but no frame", "the camera opened but delivers nothing: another process holding it?");
    else if ((width && w != width) || (height && h != height))
      report.fail("frames", expected, found, "the camera does not give the configured size: set ~width/~height to one it supports");
    else if (fps > 0 && frames / elapsed < 0.7 * fps)
      report.warn("frames", expected, found, "fewer frames than configured: light (exposure), USB bandwidth or CPU");
    else
      report.ok("frames", expected, found);
  }

  bool service() override {
    cv::Mat frame;
    ros::Time stamp;
    CameraState::Ptr s(new CameraState);
    {
      std::lock_guard lk(mutex_);
      s->open = open_;
      s->device = source_->device();
      s->frames = frames_;
      s->failed_reads = failed_;
      s->reopens = reopens_;
      if (!open_) {
        fail(error_.empty() ? "camera not open yet" : error_);
        return false;
      }
      if (last_frame_.isZero() || (ros::Time::now() - last_frame_).toSec() > stale_after_) {
        fail("no frame from " + source_->device() + " for " + std::to_string(stale_after_) + " s");
        return false;
      }
      if (newest_seq_ == published_seq_) return true;  // the camera is slower than our rate: nothing new
      published_seq_ = newest_seq_;
      frame = newest_;  // shares the buffer; the grabber writes a new Mat, never into this one
      stamp = last_frame_;
    }
    sensor_msgs::Image::Ptr img(new sensor_msgs::Image);
    img->header.stamp = stamp;
    img->header.frame_id = frame_id_;
    img->height = static_cast<uint32_t>(frame.rows);
    img->width = static_cast<uint32_t>(frame.cols);
    img->encoding = sensor_msgs::image_encodings::BGR8;
    img->is_bigendian = 0;
    img->step = static_cast<uint32_t>(frame.cols * 3);
    img->data.resize(static_cast<std::size_t>(img->step) * frame.rows);
    for (int r = 0; r < frame.rows; ++r) std::memcpy(&img->data[r * img->step], frame.ptr(r), img->step);
    image_pub_.publish(img);
    s->header.stamp = stamp;
    s->width = img->width;
    s->height = img->height;
    state_pub_.publish(s);
    return true;
  }

  void halt() override {}  // a sensor: nothing to make safe

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    std::lock_guard lk(mutex_);
    stat.add("device", source_->device());
    stat.add("open", open_ ? "yes" : "no");
    stat.add("frames", frames_);
    stat.add("failed reads", failed_);
    stat.add("reopens", reopens_);
    stat.addf("size", "%dx%d", newest_.cols, newest_.rows);
  }

 private:
  void grab() {
    bool was_open = false;
    int consecutive_failures = 0;
    while (running_) {
      std::string err;
      if (!source_->isOpen()) {
        if (!source_->open(err)) {
          setOpen(false, err);
          for (double t = 0; t < reopen_period_ && running_; t += 0.05) std::this_thread::sleep_for(std::chrono::milliseconds(50));
          continue;
        }
        std::lock_guard lk(mutex_);
        if (was_open) ++reopens_;
        was_open = true;
        open_ = true;
        consecutive_failures = 0;
      }
      cv::Mat frame;
      if (!source_->read(frame)) {
        std::lock_guard lk(mutex_);
        ++failed_;
        if (++consecutive_failures >= 3) {  // the device or stream is gone: start over
          source_->close();
          open_ = false;
          error_ = "camera " + source_->device() + " stopped delivering frames";
        }
        continue;
      }
      consecutive_failures = 0;
      if (frame.type() != CV_8UC3) {
        std::lock_guard lk(mutex_);
        ++failed_;
        continue;
      }
      std::lock_guard lk(mutex_);
      newest_ = frame;
      ++newest_seq_;
      ++frames_;
      last_frame_ = ros::Time::now();
    }
    source_->close();
  }

  void setOpen(bool open, const std::string& err) {
    std::lock_guard lk(mutex_);
    open_ = open;
    if (!err.empty()) error_ = err;
  }

  std::string device_;  // the parameters configure() read
  int width_ = 0, height_ = 0;
  double fps_ = 0.0, check_window_ = 2.0;
  std::unique_ptr<transport::CameraSource> source_;  // grabber thread only (device() is const)
  double reopen_period_ = 1.0, stale_after_ = 1.0;
  std::string frame_id_;
  ros::Publisher image_pub_, state_pub_;
  std::atomic<bool> running_{false};
  std::thread grabber_;

  robot_core::PriorityInheritanceMutex mutex_;
  bool open_ = false;
  std::string error_;
  cv::Mat newest_;
  unsigned long newest_seq_ = 0, published_seq_ = 0;
  ros::Time last_frame_;
  uint32_t frames_ = 0, failed_ = 0, reopens_ = 0;
};

}  // namespace hcl_drivers

HCL_EXPORT_BOARD(Camera,
                 "Camera through OpenCV VideoCapture (V4L2 index/path or a stream URL): sensor_msgs/Image.")
