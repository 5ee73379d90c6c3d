#include "scene_renderer.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace robot_sim {

const cv::Scalar kTableColour(60, 150, 60);
const cv::Scalar kOutsideColour(90, 90, 90);
const cv::Scalar kOpponentColour(30, 30, 30);
const cv::Scalar kRobotColour(200, 80, 20);
namespace {
const cv::Scalar kBorderColour(230, 230, 230);
constexpr double kOpponentHeight = 0.35;
}  // namespace

cv::Scalar elementColour(const std::string& kind) {
  if (kind.find("red") != std::string::npos) return {40, 40, 220};
  if (kind.find("white") != std::string::npos) return {245, 245, 245};
  if (kind.find("green") != std::string::npos) return {40, 200, 40};
  if (kind.find("blue") != std::string::npos) return {200, 60, 30};
  if (kind.find("yellow") != std::string::npos) return {30, 220, 230};
  return {0, 140, 255};  // anything else: orange, visible on the table
}

namespace {

cv::Mat renderTop(const WorldSnapshot& w, const CameraModel& c) {
  cv::Mat img(c.height, c.width, CV_8UC3, kOutsideColour);
  // Fit the table with a margin; image x = map x, image y = -map y (map y points up).
  const double margin = 0.1;
  const double s = std::min(c.width / (w.table_length + 2 * margin), c.height / (w.table_width + 2 * margin));
  const double ox = (c.width - s * w.table_length) / 2.0, oy = (c.height - s * w.table_width) / 2.0;
  auto px = [&](double x, double y) { return cv::Point(int(std::lround(ox + s * x)), int(std::lround(oy + s * (w.table_width - y)))); };
  cv::rectangle(img, px(-0.022, -0.022), px(w.table_length + 0.022, w.table_width + 0.022), kBorderColour, cv::FILLED);
  cv::rectangle(img, px(0, 0), px(w.table_length, w.table_width), kTableColour, cv::FILLED);
  for (const auto& e : w.elements) {
    if (e.carried) continue;
    cv::circle(img, px(e.pose.x, e.pose.y), std::max(1, int(std::lround(s * e.radius))), elementColour(e.kind), cv::FILLED, cv::LINE_AA);
  }
  if (w.opponent_radius > 0)
    cv::circle(img, px(w.opponent.x, w.opponent.y), int(std::lround(s * w.opponent_radius)), kOpponentColour, cv::FILLED, cv::LINE_AA);
  if (w.robot_radius > 0) {
    cv::circle(img, px(w.robot.x, w.robot.y), int(std::lround(s * w.robot_radius)), kRobotColour, cv::FILLED, cv::LINE_AA);
    cv::line(img, px(w.robot.x, w.robot.y),
             px(w.robot.x + w.robot_radius * std::cos(w.robot.theta), w.robot.y + w.robot_radius * std::sin(w.robot.theta)),
             kBorderColour, 2);
  }
  return img;
}

// Pinhole camera on the robot. Camera axes: forward = base_link x tilted down by pitch.
struct Pinhole {
  double f, cx, cy, cam_x, cam_y, cam_z, yaw, pitch;
  // World point -> pixel; false when behind the camera.
  bool project(double x, double y, double z, cv::Point2d& p, double& depth) const {
    const double dx = x - cam_x, dy = y - cam_y, dz = z - cam_z;
    // into the robot's heading frame
    const double fx = std::cos(yaw) * dx + std::sin(yaw) * dy;
    const double ly = -std::sin(yaw) * dx + std::cos(yaw) * dy;
    // pitch down: forward axis rotates towards -z
    const double fwd = std::cos(pitch) * fx - std::sin(pitch) * dz;
    const double up = std::sin(pitch) * fx + std::cos(pitch) * dz;
    if (fwd <= 0.01) return false;
    depth = fwd;
    p = {cx - f * ly / fwd, cy - f * up / fwd};
    return true;
  }
};

cv::Mat renderFront(const WorldSnapshot& w, const CameraModel& c) {
  cv::Mat img(c.height, c.width, CV_8UC3, cv::Scalar(200, 190, 180));  // the hall beyond the table
  Pinhole cam;
  cam.f = (c.width / 2.0) / std::tan(c.hfov / 2.0);
  cam.cx = c.width / 2.0;
  cam.cy = c.height / 2.0;
  cam.yaw = w.robot.theta;
  cam.pitch = c.pitch;
  cam.cam_x = w.robot.x + c.x * std::cos(cam.yaw);
  cam.cam_y = w.robot.y + c.x * std::sin(cam.yaw);
  cam.cam_z = c.z;
  // Floor: cast each pixel's ray to z = 0.
  for (int v = 0; v < c.height; ++v) {
    auto* row = img.ptr<cv::Vec3b>(v);
    for (int u = 0; u < c.width; ++u) {
      const double rx = 1.0, ry = -(u - cam.cx) / cam.f, rz = -(v - cam.cy) / cam.f;  // camera frame: fwd, left, up
      // back to the heading frame (undo pitch)
      const double fx = std::cos(cam.pitch) * rx + std::sin(cam.pitch) * rz;
      const double dz = -std::sin(cam.pitch) * rx + std::cos(cam.pitch) * rz;
      if (dz >= -1e-6) continue;  // above the horizon
      const double t = cam.cam_z / -dz;
      const double hx = fx * t, hy = ry * t;
      const double x = cam.cam_x + std::cos(cam.yaw) * hx - std::sin(cam.yaw) * hy;
      const double y = cam.cam_y + std::sin(cam.yaw) * hx + std::cos(cam.yaw) * hy;
      const bool on = x >= 0 && x <= w.table_length && y >= 0 && y <= w.table_width;
      const bool border = !on && x >= -0.022 && x <= w.table_length + 0.022 && y >= -0.022 && y <= w.table_width + 0.022;
      const cv::Scalar& col = on ? kTableColour : border ? kBorderColour : kOutsideColour;
      row[u] = cv::Vec3b(uchar(col[0]), uchar(col[1]), uchar(col[2]));
    }
  }
  // Upright cylinders, far to near.
  struct Obj {
    double x, y, r, h;
    cv::Scalar colour;
    double depth;
  };
  std::vector<Obj> objs;
  for (const auto& e : w.elements)
    if (!e.carried) objs.push_back({e.pose.x, e.pose.y, e.radius, std::max(e.height, 2 * e.radius), elementColour(e.kind), 0});
  if (w.opponent_radius > 0) objs.push_back({w.opponent.x, w.opponent.y, w.opponent_radius, kOpponentHeight, kOpponentColour, 0});
  for (auto& o : objs) {
    cv::Point2d p;
    double d = -1;
    if (!cam.project(o.x, o.y, 0, p, d)) d = -1;
    o.depth = d;
  }
  std::sort(objs.begin(), objs.end(), [](const Obj& a, const Obj& b) { return a.depth > b.depth; });
  for (const auto& o : objs) {
    if (o.depth <= 0) continue;
    cv::Point2d bottom, top;
    double db, dt;
    if (!cam.project(o.x, o.y, 0, bottom, db) || !cam.project(o.x, o.y, o.h, top, dt)) continue;
    const double half = cam.f * o.r / db;
    if (o.h <= 2 * o.r + 1e-9) {  // a ball: a disc
      cv::circle(img, (bottom + top) * 0.5, std::max(1, int(std::lround(half))), o.colour, cv::FILLED, cv::LINE_AA);
    } else {
      cv::rectangle(img, cv::Point(int(bottom.x - half), int(top.y)), cv::Point(int(bottom.x + half), int(bottom.y)), o.colour,
                    cv::FILLED);
    }
  }
  return img;
}

}  // namespace

cv::Mat renderScene(const WorldSnapshot& world, const CameraModel& camera) {
  return camera.mount == "front" ? renderFront(world, camera) : renderTop(world, camera);
}

}  // namespace robot_sim
