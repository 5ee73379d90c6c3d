#include "hcl_drivers/transport/camera_source.h"

#include <algorithm>
#include <cctype>

namespace hcl_drivers {
namespace transport {

CameraSource::CameraSource(std::string device, int width, int height, double fps)
    : device_(std::move(device)), width_(width), height_(height), fps_(fps) {}

bool CameraSource::isV4l2(const std::string& device, int* index) {
  if (!device.empty() && device.size() <= 3 && std::all_of(device.begin(), device.end(), ::isdigit)) {
    if (index) *index = std::stoi(device);
    return true;
  }
  if (device.rfind("/dev/video", 0) == 0) {
    if (index) *index = -1;
    return true;
  }
  return false;
}

bool CameraSource::open(std::string& error) {
  close();
  int index = -1;
  bool ok;
  if (isV4l2(device_, &index)) {
    ok = index >= 0 ? cap_.open(index, cv::CAP_V4L2) : cap_.open(device_, cv::CAP_V4L2);
    if (ok) {
      if (width_ > 0) cap_.set(cv::CAP_PROP_FRAME_WIDTH, width_);
      if (height_ > 0) cap_.set(cv::CAP_PROP_FRAME_HEIGHT, height_);
      if (fps_ > 0) cap_.set(cv::CAP_PROP_FPS, fps_);
      cap_.set(cv::CAP_PROP_BUFFERSIZE, 1);  // newest frame, not a queue of old ones
    }
  } else if (device_.find("://") != std::string::npos) {
    // A stream URL (http/rtsp MJPEG, H.264): FFmpeg, not the image-sequence backend that
    // CAP_ANY would try (and complain about) first.
    ok = cap_.open(device_, cv::CAP_FFMPEG);
  } else {
    ok = cap_.open(device_, cv::CAP_ANY);  // a video file, a GStreamer pipeline, ...
  }
  if (!ok || !cap_.isOpened()) {
    error = "OpenCV VideoCapture cannot open '" + device_ + "'";
    cap_.release();
    return false;
  }
  return true;
}

void CameraSource::close() { cap_.release(); }

bool CameraSource::read(cv::Mat& frame) { return cap_.isOpened() && cap_.read(frame) && !frame.empty(); }

}  // namespace transport
}  // namespace hcl_drivers
