// The estimate's cluster (mcl/clusters.h): on a two-cluster cloud the heaviest cluster's
// covariance is that of one mode, while the whole set's (what amcl and mrpt_localization
// report) spans the gap between the modes; a cluster across +-pi stays one cluster.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hal_nodes/mcl/clusters.h"

using namespace hal_nodes::mcl;

namespace {

void addMode(ParticleSet& set, std::mt19937& gen, std::size_t n, Pose2D at, double std_xy, double std_theta) {
  std::normal_distribution<double> g(0.0, 1.0);
  for (std::size_t i = 0; i < n; ++i) {
    set.x.push_back(at.x + std_xy * g(gen));
    set.y.push_back(at.y + std_xy * g(gen));
    set.theta.push_back(wrapAngle(at.theta + std_theta * g(gen)));
    set.w.push_back(1.0);
  }
}

}  // namespace

TEST(Clusters, TwoModesGiveTheHeaviestModesCovarianceNotTheGap) {
  std::mt19937 gen(3);
  ParticleSet set;
  addMode(set, gen, 1400, {0.5, 0.5, 0.0}, 0.02, 0.03);        // 70 % of the weight
  addMode(set, gen, 600, {2.5, 1.5, M_PI - 0.2}, 0.02, 0.03);  // the mirror place, 2.2 m away
  Clustering clustering(0.10, 0.20);
  const ClusterStats best = clustering.heaviest(set);
  const ClusterStats whole = weightedStats(set, circularMean(set));
  EXPECT_EQ(clustering.count(), 2u);
  EXPECT_NEAR(best.weight, 0.7, 1e-9);
  EXPECT_EQ(best.particles, 1400u);
  EXPECT_NEAR(best.mean.x, 0.5, 0.005);
  EXPECT_NEAR(best.mean.y, 0.5, 0.005);
  EXPECT_NEAR(best.mean.theta, 0.0, 0.01);
  // One mode's spread: 2 cm, 0.03 rad.
  EXPECT_NEAR(std::sqrt(best.cov[0]), 0.02, 0.003);
  EXPECT_NEAR(std::sqrt(best.cov[4]), 0.02, 0.003);
  EXPECT_NEAR(std::sqrt(best.cov[8]), 0.03, 0.005);
  // The whole set's: 0.7 * 0.3 * 2^2 m^2 in x, a mean in between where no particle is.
  EXPECT_NEAR(whole.cov[0], 0.84, 0.02);
  EXPECT_NEAR(whole.cov[4], 0.21, 0.01);
  EXPECT_NEAR(whole.mean.x, 1.1, 0.01);
  EXPECT_GT(whole.cov[0], 1000.0 * best.cov[0]);
}

TEST(Clusters, AModeAcrossPiIsOneCluster) {
  std::mt19937 gen(5);
  ParticleSet set;
  addMode(set, gen, 1000, {1.0, 1.0, M_PI}, 0.02, 0.1);  // headings on both sides of +-pi
  Clustering clustering(0.10, 0.20);
  const ClusterStats best = clustering.heaviest(set);
  EXPECT_EQ(clustering.count(), 1u);
  EXPECT_NEAR(best.weight, 1.0, 1e-9);
  EXPECT_NEAR(std::fabs(best.mean.theta), M_PI, 0.02);
  EXPECT_NEAR(std::sqrt(best.cov[8]), 0.1, 0.01);
}

TEST(Clusters, WeightsNotCountsPickTheCluster) {
  std::mt19937 gen(7);
  ParticleSet set;
  addMode(set, gen, 300, {0.5, 0.5, 0.0}, 0.02, 0.03);
  addMode(set, gen, 700, {2.0, 1.0, 1.0}, 0.02, 0.03);
  for (std::size_t i = 0; i < 300; ++i) set.w[i] = 5.0;  // fewer particles, more weight
  Clustering clustering(0.10, 0.20);
  const ClusterStats best = clustering.heaviest(set);
  EXPECT_NEAR(best.mean.x, 0.5, 0.01);
  EXPECT_NEAR(best.weight, 1500.0 / 2200.0, 1e-9);
}
