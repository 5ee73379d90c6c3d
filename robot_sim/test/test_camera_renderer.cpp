// The simulated camera's renderer: what a top and a front camera see of a known scene.
#include <gtest/gtest.h>

#include "../src/firmware/camera/scene_renderer.h"

using namespace robot_sim;

namespace {
bool near(const cv::Vec3b& px, const cv::Scalar& c, int tol = 25) {
  for (int i = 0; i < 3; ++i)
    if (std::abs(px[i] - static_cast<int>(c[i])) > tol) return false;
  return true;
}
WorldSnapshot scene() {
  WorldSnapshot w;
  w.robot = {0.5, 1.05, 0.0};  // mid-height on the left, facing +x
  w.robot_radius = 0.15;
  w.opponent = {2.5, 1.05, 3.14};
  w.opponent_radius = 0.15;
  GameElement red;
  red.kind = "ball_red";
  red.pose = {1.5, 1.05, 0};
  red.radius = 0.04;
  red.height = 0.08;
  w.elements.push_back(red);
  GameElement white = red;
  white.kind = "ball_white";
  white.pose = {1.5, 0.3, 0};
  w.elements.push_back(white);
  return w;
}
}  // namespace

TEST(CameraRenderer, TopViewShowsTableElementsOpponentAndRobotWhereTheyAre) {
  CameraModel c;  // top, 320x240
  const cv::Mat img = renderScene(scene(), c);
  ASSERT_EQ(img.cols, 320);
  ASSERT_EQ(img.rows, 240);
  ASSERT_EQ(img.type(), CV_8UC3);
  // Same mapping as the renderer: table 3.0 x 2.1 + 0.1 margins fit into 320 x 240.
  const double s = std::min(320 / 3.2, 240 / 2.3);
  const double ox = (320 - s * 3.0) / 2, oy = (240 - s * 2.1) / 2;
  auto at = [&](double x, double y) { return img.at<cv::Vec3b>(int(oy + s * (2.1 - y)), int(ox + s * x)); };
  EXPECT_TRUE(near(at(1.0, 0.6), kTableColour));
  EXPECT_TRUE(near(at(1.5, 1.05), elementColour("ball_red")));
  EXPECT_TRUE(near(at(1.5, 0.3), elementColour("ball_white")));
  EXPECT_TRUE(near(at(2.5, 1.05), kOpponentColour));
  EXPECT_TRUE(near(at(0.45, 1.0), kRobotColour));
  EXPECT_TRUE(near(img.at<cv::Vec3b>(1, 1), kOutsideColour));
}

TEST(CameraRenderer, FrontViewSeesTheBallAheadCentredAndTheTableBelow) {
  CameraModel c;
  c.mount = "front";
  WorldSnapshot w = scene();
  w.opponent_radius = 0;  // nothing behind the ball
  const cv::Mat img = renderScene(w, c);
  // The red ball is straight ahead: centre column, below the horizon.
  int red_rows = 0, red_cols_left = 0, red_cols_right = 0;
  for (int v = 0; v < img.rows; ++v)
    for (int u = 0; u < img.cols; ++u)
      if (near(img.at<cv::Vec3b>(v, u), elementColour("ball_red"))) {
        ++red_rows;
        (u < img.cols / 2 ? red_cols_left : red_cols_right)++;
      }
  EXPECT_GT(red_rows, 10);
  EXPECT_NEAR(red_cols_left, red_cols_right, 0.3 * red_rows + 2);  // symmetric about the centre
  // The bottom rows are table in front of the robot.
  EXPECT_TRUE(near(img.at<cv::Vec3b>(img.rows - 2, img.cols / 2), kTableColour));
  // Turned around (facing the near border, 0.5 m behind), the ball is out of view.
  w.robot.theta = 3.14159;
  const cv::Mat back = renderScene(w, c);
  int red_back = 0;
  for (int v = 0; v < back.rows; ++v)
    for (int u = 0; u < back.cols; ++u) red_back += near(back.at<cv::Vec3b>(v, u), elementColour("ball_red"));
  EXPECT_EQ(red_back, 0);
}

TEST(CameraRenderer, OpponentHidesWhatIsBehindIt) {
  CameraModel c;
  c.mount = "front";
  WorldSnapshot w = scene();
  w.elements[0].pose = {2.8, 1.05, 0};  // the red ball right behind the opponent at 2.5
  const cv::Mat img = renderScene(w, c);
  int red = 0, dark = 0;
  for (int v = 0; v < img.rows; ++v)
    for (int u = 0; u < img.cols; ++u) {
      red += near(img.at<cv::Vec3b>(v, u), elementColour("ball_red"));
      dark += near(img.at<cv::Vec3b>(v, u), kOpponentColour, 10);
    }
  EXPECT_EQ(red, 0);
  EXPECT_GT(dark, 50);
}
