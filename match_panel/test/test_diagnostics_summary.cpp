#include <gtest/gtest.h>

#include "match_panel/diagnostics_summary.h"

using diagnostic_msgs::DiagnosticArray;
using diagnostic_msgs::DiagnosticStatus;
using match_panel::DiagnosticsSummary;

namespace {

DiagnosticStatus status(const std::string& name, int level, const std::string& message) {
  DiagnosticStatus s;
  s.name = name;
  s.level = level;
  s.message = message;
  return s;
}

}  // namespace

TEST(DiagnosticsSummary, WorstFirstThenByName) {
  DiagnosticsSummary d;
  DiagnosticArray a;
  a.status = {status("odometry", DiagnosticStatus::OK, "ok"), status("beacons", DiagnosticStatus::WARN, "2 of 3"),
              status("arm", DiagnosticStatus::OK, "ok"), status("drive", DiagnosticStatus::ERROR, "no answer")};
  d.update(a, ros::Time(10.0));
  const auto lines = d.lines(ros::Time(10.5));
  ASSERT_EQ(4u, lines.size());
  EXPECT_EQ("drive", lines[0].name);
  EXPECT_EQ("no answer", lines[0].message);
  EXPECT_EQ("beacons", lines[1].name);
  EXPECT_EQ("arm", lines[2].name);
  EXPECT_EQ("odometry", lines[3].name);
  EXPECT_FALSE(lines[0].stale);
}

TEST(DiagnosticsSummary, WorstOfOneNameInOneArray) {
  DiagnosticsSummary d;
  DiagnosticArray a;
  a.status = {status("drive", DiagnosticStatus::OK, "fine"), status("drive", DiagnosticStatus::ERROR, "stalled"),
              status("drive", DiagnosticStatus::WARN, "slow")};
  d.update(a, ros::Time(1.0));
  const auto lines = d.lines(ros::Time(1.0));
  ASSERT_EQ(1u, lines.size());
  EXPECT_EQ(DiagnosticStatus::ERROR, lines[0].level);
  EXPECT_EQ("stalled", lines[0].message);
}

TEST(DiagnosticsSummary, LaterArrayReplacesAndOthersStay) {
  DiagnosticsSummary d;
  DiagnosticArray a, b;
  a.status = {status("drive", DiagnosticStatus::ERROR, "stalled"), status("arm", DiagnosticStatus::OK, "ok")};
  b.status = {status("drive", DiagnosticStatus::OK, "moving")};  // another publisher's array: arm is not in it
  d.update(a, ros::Time(1.0));
  d.update(b, ros::Time(2.0));
  const auto lines = d.lines(ros::Time(2.0));
  ASSERT_EQ(2u, lines.size());
  EXPECT_EQ("arm", lines[0].name);  // both OK: by name
  EXPECT_EQ("drive", lines[1].name);
  EXPECT_EQ("moving", lines[1].message);
}

TEST(DiagnosticsSummary, NotUpdatedForThreeSecondsIsStale) {
  DiagnosticsSummary d;
  DiagnosticArray a, b;
  a.status = {status("camera", DiagnosticStatus::OK, "30 fps")};
  b.status = {status("drive", DiagnosticStatus::ERROR, "stalled")};
  d.update(a, ros::Time(100.0));
  d.update(b, ros::Time(102.5));
  auto lines = d.lines(ros::Time(103.0));
  EXPECT_FALSE(lines[1].stale);  // 3.0 s: not yet
  lines = d.lines(ros::Time(103.2));
  ASSERT_EQ(2u, lines.size());
  EXPECT_EQ("camera", lines[0].name);  // STALE ranks above ERROR
  EXPECT_TRUE(lines[0].stale);
  EXPECT_EQ(DiagnosticStatus::STALE, lines[0].level);
  // Not "STALE: 30 fps": how long it has been silent, and what it said last as such.
  EXPECT_EQ("no report for 3 s (last said: 30 fps)", lines[0].message);
  EXPECT_EQ("STALE", match_panel::levelName(lines[0].level));
  EXPECT_EQ("drive", lines[1].name);
}

TEST(DiagnosticsSummary, LevelNames) {
  EXPECT_EQ("OK", match_panel::levelName(0));
  EXPECT_EQ("WARN", match_panel::levelName(1));
  EXPECT_EQ("ERROR", match_panel::levelName(2));
  EXPECT_EQ("STALE", match_panel::levelName(3));
}
