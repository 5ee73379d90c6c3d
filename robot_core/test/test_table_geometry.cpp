#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "robot_core/table_geometry.h"

using robot_core::Circle;
using robot_core::Rect;
using robot_core::TableGeometry;

namespace {
TableGeometry vectorTable(const YAML::Node& doc) {
  std::vector<Rect> blocks;
  for (const auto& b : doc["table"]["blocks"])
    blocks.push_back({b[0].as<double>(), b[1].as<double>(), b[2].as<double>(), b[3].as<double>()});
  return TableGeometry(doc["table"]["length"].as<double>(), doc["table"]["width"].as<double>(), blocks);
}
}  // namespace

// The vectors the Python twin checks too.
TEST(TableGeometry, SharedVectors) {
  const YAML::Node doc = YAML::LoadFile(TEST_VECTORS);
  const TableGeometry table = vectorTable(doc);
  ASSERT_GE(doc["cases"].size(), 10u);
  for (const auto& c : doc["cases"]) {
    std::vector<Circle> circles;
    for (const auto& k : c["circles"]) circles.push_back({k[0].as<double>(), k[1].as<double>(), k[2].as<double>()});
    const auto apex = c["apex"];
    EXPECT_NEAR(table.coneRange(apex[0].as<double>(), apex[1].as<double>(), apex[2].as<double>(),
                                c["beam_width"].as<double>(), circles),
                c["range"].as<double>(), 1e-9)
        << c["name"].as<std::string>();
  }
}

// Exact means: never farther than the nearest of a dense ray fan, and never nearer than it by
// more than the fan's spacing allows.
TEST(TableGeometry, ConeRangeIsTheMinimumOverADenseRayFan) {
  const TableGeometry table(3.0, 2.1, {{1.3, 0.0, 1.7, 0.3}, {0.0, 1.8, 0.4, 2.1}});
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(0.05, 2.95), uy(0.05, 2.05), ua(-M_PI, M_PI), uw(0.0, 1.2),
      ur(0.05, 0.2);
  int open = 0;
  for (int i = 0; i < 300; ++i) {
    const double x = ux(rng), y = uy(rng), a = ua(rng), width = uw(rng);
    const std::vector<Circle> circles{{ux(rng), uy(rng), ur(rng)}};
    double fan = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= 4000; ++k) fan = std::min(fan, table.rayRange(x, y, a + width * (k / 4000.0 - 0.5), circles));
    const double cone = table.coneRange(x, y, a, width, circles);
    EXPECT_LE(cone, fan + 1e-9) << x << " " << y << " " << a << " " << width;
    EXPECT_GE(cone, fan - 2e-3) << x << " " << y << " " << a << " " << width;
    open += table.open(x, y) ? 1 : 0;
  }
  EXPECT_GT(open, 200);  // most apexes were on the open table: the check is not all zeros
}

TEST(TableGeometry, RaysAndEdges) {
  const TableGeometry table(3.0, 2.1, {{1.3, 0.0, 1.7, 0.3}});
  EXPECT_NEAR(table.rayRange(1.0, 1.0, 0.0), 2.0, 1e-12);
  EXPECT_NEAR(table.rayRange(1.0, 1.0, M_PI), 1.0, 1e-12);
  EXPECT_NEAR(table.rayRange(1.0, 1.0, 0.0, {{1.5, 1.0, 0.1}}), 0.4, 1e-12);
  EXPECT_NEAR(table.rayRange(1.0, 1.0, M_PI, {{1.5, 1.0, 0.1}}), 1.0, 1e-12);  // a circle behind is not seen
  EXPECT_EQ(table.rayRange(std::nan(""), 1.0, 0.0), 0.0);
  EXPECT_NEAR(table.distanceToEdge(0.2, 1.0), 0.2, 1e-12);
  EXPECT_NEAR(table.distanceToEdge(1.5, 0.5), 0.2, 1e-12);
  EXPECT_EQ(table.distanceToEdge(-1.0, 1.0), 0.0);
  EXPECT_FALSE(table.open(1.5, 0.2));
  EXPECT_TRUE(table.open(1.5, 0.4));
  EXPECT_THROW(TableGeometry(0.0, 2.1), std::invalid_argument);
  EXPECT_THROW(TableGeometry(3.0, 2.1, {{1.0, 0.0, 1.0, 0.3}}), std::invalid_argument);
}
