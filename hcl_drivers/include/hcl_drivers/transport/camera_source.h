// A camera opened through OpenCV's VideoCapture, from a device string:
//   "0", "1", ...          V4L2 device index (/dev/videoN), the robot's USB webcams
//   "/dev/video0"          V4L2 device path
//   anything else          a URL or file OpenCV opens itself (FFmpeg/GStreamer backends),
//                          e.g. the simulator's MJPEG stream http://127.0.0.1:27220/camera.mjpg
// The same VideoCapture path serves all of them; only the string differs.
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

#include <string>

namespace hcl_drivers {
namespace transport {

class CameraSource {
 public:
  // width/height/fps: requested from V4L2 devices (0 = the device's default); ignored by streams.
  CameraSource(std::string device, int width, int height, double fps);

  // true: the string names a V4L2 device (index or /dev/video*).
  static bool isV4l2(const std::string& device, int* index = nullptr);

  bool open(std::string& error);
  void close();
  bool isOpen() const { return cap_.isOpened(); }
  // Blocks until the next frame (at most about one frame period on a live camera).
  bool read(cv::Mat& frame);
  const std::string& device() const { return device_; }

 private:
  std::string device_;
  int width_, height_;
  double fps_;
  cv::VideoCapture cap_;
};

}  // namespace transport
}  // namespace hcl_drivers
