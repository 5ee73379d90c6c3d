// Vision: finds the year's game elements (2008: balls by colour; 2009: columns) in the
// camera's images and publishes where they stand on the table: hal_nodes/GameElements on
// ~elements (/hal/vision/elements) in `map` with a covariance, and ~debug_image with the
// detections drawn (only rendered while someone subscribes).
//
// How: each configured kind is a colour range in HSV; its blobs (opened to remove speckle,
// at least ~min_area_px) are candidates. A blob's anchor pixel (its centre for a ball, the
// middle of its bottom edge for a column standing on the table) is cast as a ray through a
// pinhole camera (~horizontal_fov, or fx/fy/cx/cy) from the camera's optical frame, looked up
// in tf at the image's stamp (URDF via robot_state_publisher, map -> odom from localization),
// and intersected with the horizontal plane at the anchor's height. Points off the table
// are dropped. The covariance grows with distance: a pixel error of ~pixel_std is
// ~pixel_std/fx rad across the ray, stretched along it by 1/sin(depression angle).
// The device samples the newest image at its ~rate.
//
// Parameters: read and described in configure() (the table: hal_nodes/PARAMETERS.md, make docs).
#include <cv_bridge/cv_bridge.h>
#include <hal_nodes/GameElements.h>
#include <sensor_msgs/Image.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <Eigen/Geometry>
#include <atomic>
#include <deque>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "hal_nodes/device_nodelet.h"
#include <robot_core/params.h>

namespace hal_nodes {

class VisionDevice : public Device {
 public:
  void configure(const robot_core::Params& params) override {
    params.describe("map_frame", "the frame the elements are published in");
    map_frame_ = params.optionalString("map_frame", "map");
    params.describe("camera_frame", "the camera's optical frame ('': the image's frame_id)");
    camera_frame_ = params.optionalString("camera_frame", "");
    params.describe("horizontal_fov", "[rad] the camera's horizontal field of view (when fx is not given)");
    hfov_ = params.optionalDouble("horizontal_fov", 1.0);
    params.requireInRange("horizontal_fov", hfov_, 0.1, 3.0);
    params.describe("fx", "[px] focal length in x (<= 0: from horizontal_fov)");
    fx_ = params.optionalDouble("fx", 0.0);
    params.describe("fy", "[px] focal length in y (<= 0: fx)");
    fy_ = params.optionalDouble("fy", fx_);
    params.describe("cx", "[px] principal point x (< 0: the image's centre)");
    cx_ = params.optionalDouble("cx", -1.0);
    params.describe("cy", "[px] principal point y (< 0: the image's centre)");
    cy_ = params.optionalDouble("cy", -1.0);
    params.describe("pixel_std", "[px] the anchor pixel's error, for the covariance");
    pixel_std_ = params.optionalDouble("pixel_std", 2.0);
    params.requirePositive("pixel_std", pixel_std_);
    params.describe("max_input_age", "[s] an older image makes the device unavailable");
    max_input_age_ = params.optionalDouble("max_input_age", 0.5);
    params.requirePositive("max_input_age", max_input_age_);
    params.describe("table/length", "[m] x extent of the table: points off it are dropped");
    table_length_ = params["table"].optionalDouble("length", 3.0);
    params.describe("table/width", "[m] y extent of the table: points off it are dropped");
    table_width_ = params["table"].optionalDouble("width", 2.1);
    kinds_.clear();
    params.describe("elements", "the kinds of game element to find, by name: a colour range each");
    for (const auto& kind : params.requireBlockNames("elements")) {
      const robot_core::Params p = params.block("elements/" + kind);
      Kind k;
      k.name = kind;
      p.describe("hsv_min", "[h, s, v] lower bound, OpenCV ranges (h 0..180, s and v 0..255)");
      const auto lo = p.optionalDoubleList("hsv_min");
      p.describe("hsv_max", "[h, s, v] upper bound; h_min > h_max wraps round (reds)");
      const auto hi = p.optionalDoubleList("hsv_max");
      if (lo.size() != 3 || hi.size() != 3)
        throw robot_core::ParameterError("parameters " + p.qualified("hsv_min") +
                                         " and hsv_max must be [h, s, v] (h 0..180, s and v 0..255)");
      k.lo = cv::Scalar(lo[0], lo[1], lo[2]);
      k.hi = cv::Scalar(hi[0], hi[1], hi[2]);
      p.describe("anchor", "the blob's pixel cast as a ray: center (a ball) or bottom (a column on the table)");
      const std::string anchor = p.optionalString("anchor", "center");
      p.requireOneOf("anchor", anchor, {"center", "bottom"});
      k.bottom = anchor == "bottom";
      p.describe("z", "[m] height of the anchor (a ball: its radius; a column: 0)");
      k.z = p.requireDouble("z");
      p.requireInRange("z", k.z, 0.0, 1.0);
      p.describe("min_area_px", "[px^2] smaller blobs are not candidates");
      k.min_area = p.optionalDouble("min_area_px", 30.0);
      p.requirePositive("min_area_px", k.min_area);
      kinds_.push_back(k);
    }
    params.describe("image", "the camera's image topic in (sensor_msgs/Image, /hcl/<board>/image)");
    image_topic_ = params.requireString("image");
  }

  void init(DeviceContext& ctx) override {
    image_ = addInput<sensor_msgs::Image>(ctx.nh, image_topic_, "image");
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(tf_buffer_);
    elements_pub_ = ctx.pnh.advertise<GameElements>("elements", 1);
    debug_pub_ = ctx.pnh.advertise<sensor_msgs::Image>("debug_image", 1);
  }

  void refresh() override {
    const auto newest = image_->fresh(max_input_age_);
    if (!newest) return setUnavailable("no fresh camera image (age " + std::to_string(image_->age()) + " s)");
    if (newest->header.stamp == last_stamp_) return;  // already processed
    LatestValue<sensor_msgs::Image>::ConstPtr img;
    geometry_msgs::TransformStamped t;
    try {
      // The pose at the image's stamp. The chain's newest link (the odometry) may not have reached
      // that stamp yet: the image then waits for a later refresh, as long as it is fresh, instead
      // of blocking this thread or failing on a few milliseconds of lag. The camera's frames
      // arrive sooner than the odometry's transform, so the newest image is often still ahead of
      // it at the next refresh too: each refresh takes the newest of the images sampled so far
      // that tf can place (taking only the newest left the elements unpublished for seconds).
      if (candidates_.empty() || candidates_.back()->header.stamp < newest->header.stamp) candidates_.push_back(newest);
      const ros::Time now = ros::Time::now();
      while (!candidates_.empty() && (candidates_.front()->header.stamp <= last_stamp_ ||
                                      (now - candidates_.front()->header.stamp).toSec() > max_input_age_))
        candidates_.pop_front();
      for (auto it = candidates_.rbegin(); it != candidates_.rend() && !img; ++it)
        if (placeable(**it)) img = *it;
      if (!img) {
        ++waits_for_tf_;
        return;
      }
      while (!candidates_.empty() && candidates_.front()->header.stamp <= img->header.stamp) candidates_.pop_front();
      t = tf_buffer_.lookupTransform(map_frame_, frameOf(*img), img->header.stamp);
    } catch (const tf2::TransformException& e) {
      return setUnavailable("no transform " + map_frame_ + " -> " + frameOf(*newest) + ": " + e.what());
    } catch (const std::runtime_error& e) {  // placeable(): the transform is too far behind
      return setUnavailable(e.what());
    }
    last_stamp_ = img->header.stamp;
    cv_bridge::CvImageConstPtr cv;
    try {
      cv = cv_bridge::toCvShare(img, "bgr8");
    } catch (const cv_bridge::Exception& e) {
      ++bad_images_;
      return setUnavailable(std::string("camera image not convertible to bgr8: ") + e.what());
    }
    setAvailable();
    const Eigen::Isometry3d T = toEigen(t);
    const double fx = fx_ > 0 ? fx_ : 0.5 * cv->image.cols / std::tan(0.5 * hfov_);
    const double fy = fy_ > 0 ? fy_ : fx;
    const double cx = cx_ >= 0 ? cx_ : 0.5 * cv->image.cols, cy = cy_ >= 0 ? cy_ : 0.5 * cv->image.rows;

    cv::Mat hsv;
    cv::cvtColor(cv->image, hsv, cv::COLOR_BGR2HSV);
    const bool debug = debug_pub_.getNumSubscribers() > 0;
    cv::Mat canvas = debug ? cv->image.clone() : cv::Mat();
    GameElements out;
    out.header.stamp = img->header.stamp;
    out.header.frame_id = map_frame_;
    for (const auto& k : kinds_) {
      cv::Mat mask = threshold(hsv, k);
      cv::morphologyEx(mask, mask, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(3, 3)));
      std::vector<std::vector<cv::Point>> contours;
      cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
      for (const auto& c : contours) {
        if (cv::contourArea(c) < k.min_area) continue;
        const cv::Rect box = cv::boundingRect(c);
        const cv::Moments mo = cv::moments(c);
        const double u = mo.m10 / mo.m00;
        const double v = k.bottom ? box.y + box.height : mo.m01 / mo.m00;
        GameElement e;
        if (!project(T, (u - cx) / fx, (v - cy) / fy, k.z, fx, e)) continue;
        e.kind = k.name;
        e.pixel_radius = 0.5 * std::max(box.width, box.height);
        out.elements.push_back(e);
        if (debug) {
          cv::rectangle(canvas, box, cv::Scalar(0, 255, 0), 2);
          cv::putText(canvas, k.name, box.tl(), cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0, 255, 0), 1);
        }
      }
    }
    elements_pub_.publish(out);
    if (debug) debug_pub_.publish(cv_bridge::CvImage(img->header, "bgr8", canvas).toImageMsg());
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) override {
    stat.add("bad images", bad_images_.load());
    stat.add("images waiting for tf", waits_for_tf_.load());
  }

 private:
  std::string frameOf(const sensor_msgs::Image& img) const { return camera_frame_.empty() ? img.header.frame_id : camera_frame_; }

  // Whether tf places the camera at the image's stamp now; false: not yet (a few milliseconds
  // behind). Throws std::runtime_error when the transform is further behind than max_input_age.
  bool placeable(const sensor_msgs::Image& img) {
    const std::string cam = frameOf(img);
    // A chain of static transforms alone has no newest stamp (0): it holds at every stamp.
    const ros::Time newest = tf_buffer_.lookupTransform(map_frame_, cam, ros::Time(0)).header.stamp;
    if (newest.isZero() || newest >= img.header.stamp) return true;
    if ((img.header.stamp - newest).toSec() <= max_input_age_) return false;
    throw std::runtime_error("no transform " + map_frame_ + " -> " + cam + " at the image's stamp: the newest is " +
                             std::to_string((img.header.stamp - newest).toSec()) + " s older");
  }

  struct Kind {
    std::string name;
    cv::Scalar lo, hi;
    bool bottom = false;
    double z = 0.0, min_area = 30.0;
  };

  static cv::Mat threshold(const cv::Mat& hsv, const Kind& k) {
    cv::Mat mask;
    if (k.lo[0] <= k.hi[0]) {
      cv::inRange(hsv, k.lo, k.hi, mask);
    } else {  // hue range across 180 (red)
      cv::Mat a, b;
      cv::inRange(hsv, k.lo, cv::Scalar(180, k.hi[1], k.hi[2]), a);
      cv::inRange(hsv, cv::Scalar(0, k.lo[1], k.lo[2]), k.hi, b);
      mask = a | b;
    }
    return mask;
  }

  static Eigen::Isometry3d toEigen(const geometry_msgs::TransformStamped& t) {
    const auto& r = t.transform.rotation;
    const auto& p = t.transform.translation;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::Quaterniond(r.w, r.x, r.y, r.z).toRotationMatrix();
    T.translation() = Eigen::Vector3d(p.x, p.y, p.z);
    return T;
  }

  // Ray (x, y, 1) in the optical frame -> point on the plane z = plane_z in map.
  bool project(const Eigen::Isometry3d& T, double x, double y, double plane_z, double fx, GameElement& e) const {
    const Eigen::Vector3d o = T.translation();
    const Eigen::Vector3d d = T.linear() * Eigen::Vector3d(x, y, 1.0);
    if (d.z() >= -1e-6) return false;  // at or above the horizon
    const double s = (plane_z - o.z()) / d.z();
    if (s <= 0) return false;
    const Eigen::Vector3d p = o + s * d;
    if (p.x() < 0 || p.y() < 0 || p.x() > table_length_ || p.y() > table_width_) return false;
    const double range = (p - o).norm();
    const double across = range * pixel_std_ / fx;
    const double horiz = std::hypot(d.x(), d.y());
    const double sin_dep = -d.z() / d.norm();
    const double along = across / std::max(sin_dep, 0.05);
    const double c = horiz > 1e-9 ? d.x() / horiz : 1.0, sn = horiz > 1e-9 ? d.y() / horiz : 0.0;
    e.pose.pose.position.x = p.x();
    e.pose.pose.position.y = p.y();
    e.pose.pose.position.z = plane_z;
    e.pose.pose.orientation.w = 1.0;
    const double a2 = along * along, b2 = across * across;
    e.pose.covariance[0] = c * c * a2 + sn * sn * b2;
    e.pose.covariance[1] = e.pose.covariance[6] = c * sn * (a2 - b2);
    e.pose.covariance[7] = sn * sn * a2 + c * c * b2;
    e.pose.covariance[14] = 1e-4;
    for (int i : {21, 28, 35}) e.pose.covariance[i] = 1e6;  // orientation unknown
    return true;
  }

  std::vector<Kind> kinds_;
  std::atomic<unsigned long> waits_for_tf_{0};  // refreshes with no image tf could place yet
  std::shared_ptr<LatestValue<sensor_msgs::Image>> image_;
  tf2_ros::Buffer tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::Publisher elements_pub_, debug_pub_;
  ros::Time last_stamp_;
  // Images sampled at earlier refreshes that tf could not place yet, oldest first (fresh ones only).
  std::deque<LatestValue<sensor_msgs::Image>::ConstPtr> candidates_;
  std::string map_frame_, camera_frame_, image_topic_;
  double hfov_ = 1.0, fx_ = 0, fy_ = 0, cx_ = -1, cy_ = -1, pixel_std_ = 2.0, max_input_age_ = 0.5;
  double table_length_ = 3.0, table_width_ = 2.1;
  std::atomic<unsigned long> bad_images_{0};  // read by diagnose() on the diagnostics thread
};

}  // namespace hal_nodes

HAL_EXPORT_DEVICE(VisionDevice, Vision,
                  "Vision: game elements found by colour in camera images, positioned on the table (map) with covariance.")
