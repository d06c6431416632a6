#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <limits>

#include "ewis/filter/resolution.hpp"
#include "filter/synth.hpp"

using namespace ewis;

TEST(Resolution, PlaneGridGivesItsSpacingExactly) {
  const auto pts = test::plane_grid(120, 80, 0.5f);
  const KdTree tree(pts);
  const ResolutionResult r = spatial_resolution(tree);
  EXPECT_EQ(r.points, pts.size());
  EXPECT_DOUBLE_EQ(r.mean_mm, 0.5);
  EXPECT_DOUBLE_EQ(r.median_mm, 0.5);
  // a strided sample of an even grid measures the same
  const ResolutionResult s = spatial_resolution(tree, 1000);
  EXPECT_DOUBLE_EQ(s.mean_mm, 0.5);
  EXPECT_EQ(s.points, 960u);  // stride ceil(9600 / 1000) = 10
}

TEST(Resolution, NonDyadicSpacing) {
  const auto pts = test::plane_grid(60, 60, 0.7f);
  const ResolutionResult r = spatial_resolution(KdTree(pts));
  EXPECT_NEAR(r.mean_mm, 0.7, 1e-5);
  EXPECT_NEAR(r.median_mm, 0.7, 1e-5);
}

TEST(Resolution, JitteredGridWithinAFewPercent) {
  // +-4% in-plane jitter and 0.02 mm noise off the plane; the nearest of ~4 jittered neighbours is on
  // average a little closer than s (about -1.2 x jitter), never farther on a grid this regular
  const auto pts = test::plane_grid(200, 200, 0.5f, 0.f, 0.02f, 0.02f, 42);
  const ResolutionResult r = spatial_resolution(KdTree(pts));
  EXPECT_NEAR(r.mean_mm, 0.5, 0.5 * 0.06);
  EXPECT_NEAR(r.median_mm, 0.5, 0.5 * 0.06);
  EXPECT_LT(r.mean_mm, 0.5);
}

TEST(Resolution, DuplicatesCountAsZeroAndNaNsAreSkipped) {
  std::vector<Eigen::Vector3f> pts = {{0, 0, 0}, {0, 0, 0}, {3, 0, 0}, {3, 0, 1}};
  const ResolutionResult r = spatial_resolution(KdTree(pts));
  EXPECT_DOUBLE_EQ(r.mean_mm, 0.5);  // 0, 0, 1, 1
  EXPECT_DOUBLE_EQ(r.median_mm, 0.5);
  pts.push_back({std::numeric_limits<float>::quiet_NaN(), 0, 0});
  const ResolutionResult n = spatial_resolution(KdTree(pts));
  EXPECT_EQ(n.points, 4u);
  EXPECT_DOUBLE_EQ(n.mean_mm, 0.5);
}

TEST(Resolution, TinyClouds) {
  EXPECT_EQ(spatial_resolution(KdTree(std::vector<Eigen::Vector3f>{})).mean_mm, 0.0);
  EXPECT_EQ(spatial_resolution(KdTree(std::vector<Eigen::Vector3f>{{1, 2, 3}})).mean_mm, 0.0);
  const ResolutionResult two = spatial_resolution(KdTree(std::vector<Eigen::Vector3f>{{0, 0, 0}, {0, 0, 2}}));
  EXPECT_DOUBLE_EQ(two.mean_mm, 2.0);
  EXPECT_DOUBLE_EQ(two.median_mm, 2.0);
}

TEST(Resolution, SameBitsForOneAndTwoThreads) {
  const auto pts = test::plane_grid(300, 300, 0.5f, 0.f, 0.1f, 0.05f, 3);
  const KdTree tree(pts);
  ResolutionResult a, b;
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
    a = spatial_resolution(tree);
  }
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
    b = spatial_resolution(tree);
  }
  EXPECT_EQ(a.mean_mm, b.mean_mm);
  EXPECT_EQ(a.median_mm, b.median_mm);
}
