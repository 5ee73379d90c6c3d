#include <gtest/gtest.h>
#include <std_msgs/Float64.h>
#include <geometry_msgs/PointStamped.h>

#include "hal_nodes/latest_value.h"

using hal_nodes::LatestValueCache;

TEST(LatestValueCache, EmptyHasNoValueAndInfiniteAge) {
  LatestValueCache<std_msgs::Float64> c;
  EXPECT_FALSE(c.newest());
  EXPECT_FALSE(c.fresh(1e9, ros::Time(10)));
  EXPECT_TRUE(std::isinf(c.age(ros::Time(10))));
  EXPECT_EQ(c.received(), 0u);
}

TEST(LatestValueCache, KeepsOnlyTheNewest) {
  LatestValueCache<std_msgs::Float64> c;
  for (int i = 0; i < 100; ++i) {
    std_msgs::Float64::Ptr m(new std_msgs::Float64);
    m->data = i;
    c.store(m, ros::Time(1.0 + 0.01 * i));
  }
  ASSERT_TRUE(c.newest());
  EXPECT_EQ(c.newest()->data, 99);
  EXPECT_EQ(c.received(), 100u);
  EXPECT_NEAR(c.age(ros::Time(2.0)), 2.0 - 1.99, 1e-9);
}

TEST(LatestValueCache, FreshnessFollowsReceiptTimeWithoutHeader) {
  LatestValueCache<std_msgs::Float64> c;
  std_msgs::Float64::Ptr m(new std_msgs::Float64);
  c.store(m, ros::Time(5.0));
  EXPECT_TRUE(c.fresh(0.5, ros::Time(5.4)));
  EXPECT_FALSE(c.fresh(0.5, ros::Time(5.6)));
}

TEST(LatestValueCache, FreshnessFollowsHeaderStampWhenPresent) {
  // A latched message received now but produced long ago is old.
  LatestValueCache<geometry_msgs::PointStamped> c;
  geometry_msgs::PointStamped::Ptr m(new geometry_msgs::PointStamped);
  m->header.stamp = ros::Time(1.0);
  c.store(m, ros::Time(100.0));
  EXPECT_NEAR(c.age(ros::Time(100.0)), 99.0, 1e-9);
  EXPECT_FALSE(c.fresh(1.0, ros::Time(100.0)));
}
