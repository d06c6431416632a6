// Radius outlier removal (paper 4.1.1): planted outliers at known places are removed, nothing else is.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <limits>
#include <numeric>

#include "ewis/filter/outlier_removal.hpp"
#include "filter/synth.hpp"

using namespace ewis;

namespace {

std::vector<std::uint32_t> iota(std::size_t n) {
  std::vector<std::uint32_t> v(n);
  std::iota(v.begin(), v.end(), 0u);
  return v;
}

// A dense plane (0.5 mm spacing, 100 x 100 mm) first, then ~40% outliers: isolated points on a 4 mm lattice
// above the plane (each alone within 3 mm) and clusters of 3 "flying pixels" 0.4 mm apart between them.
struct Planted {
  std::vector<Eigen::Vector3f> points;
  std::size_t surface = 0;
};

Planted planted_scene(float noise_sigma = 0.f, float jitter = 0.f) {
  Planted s;
  s.points = test::plane_grid(200, 200, 0.5f, 0.f, jitter, noise_sigma, 5);
  s.surface = s.points.size();
  for (int l = 0; l < 32; ++l)
    for (int j = 0; j < 25; ++j)
      for (int i = 0; i < 25; ++i) s.points.emplace_back(i * 4.f, j * 4.f, 6.f + l * 4.f);
  for (int l = 0; l < 8; ++l)
    for (int j = 0; j < 16; ++j)
      for (int i = 0; i < 16; ++i) {
        const Eigen::Vector3f c(2.f + i * 4.f, 2.f + j * 4.f, 8.f + l * 4.f);
        s.points.push_back(c);
        s.points.push_back(c + Eigen::Vector3f(0.4f, 0, 0));
        s.points.push_back(c + Eigen::Vector3f(0, 0.4f, 0));
      }
  return s;
}

}  // namespace

TEST(RadiusOutliers, DefaultParamsRemoveExactlyThePlantedOutliers) {
  const Planted s = planted_scene();
  ASSERT_GT(double(s.points.size() - s.surface) / s.points.size(), 0.35);
  const KdTree tree(s.points);
  const RadiusOutlierResult r = remove_radius_outliers(tree, {});
  EXPECT_DOUBLE_EQ(r.resolution_mm, 0.5);  // the median ignores the 40% outliers
  EXPECT_DOUBLE_EQ(r.radius_mm, 2.0);      // 4 x R
  EXPECT_EQ(r.min_neighbors, 6);           // max(6, round(0.1 x pi x 16))
  EXPECT_EQ(r.kept, iota(s.surface));      // every plane point, incl. edges and corners, and nothing else
}

TEST(RadiusOutliers, NoisyJitteredSurfaceKeptWhole) {
  const Planted s = planted_scene(0.1f, 0.1f);
  const RadiusOutlierResult r = remove_radius_outliers(KdTree(s.points), {});
  EXPECT_NEAR(r.resolution_mm, 0.5, 0.05);
  EXPECT_EQ(r.kept, iota(s.surface));
}

TEST(RadiusOutliers, ExplicitParametersPaperStyle) {
  const Planted s = planted_scene();
  RadiusOutlierParams p;
  p.radius_mm = 2.0;
  p.min_neighbors = 4;  // clusters of 3 see 2 others: removed
  const RadiusOutlierResult r = remove_radius_outliers(KdTree(s.points), p);
  EXPECT_EQ(r.resolution_mm, 0.0);  // not measured
  EXPECT_EQ(r.radius_mm, 2.0);
  EXPECT_EQ(r.min_neighbors, 4);
  EXPECT_EQ(r.kept, iota(s.surface));
  // k = 2 keeps the 3-point clusters but not the isolated points
  p.min_neighbors = 2;
  const RadiusOutlierResult r2 = remove_radius_outliers(KdTree(s.points), p);
  EXPECT_EQ(r2.kept.size(), s.surface + 8 * 16 * 16 * 3);
}

TEST(RadiusOutliers, ExactlyKOthersIsEnough) {
  // a point with exactly k others within r (one of them exactly at r) stays; with k - 1 it goes
  const std::vector<Eigen::Vector3f> pts = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {50, 0, 0}};
  RadiusOutlierParams p;
  p.radius_mm = 1.0;
  p.min_neighbors = 3;
  const RadiusOutlierResult r = remove_radius_outliers(KdTree(pts), p);
  EXPECT_EQ(r.kept, std::vector<std::uint32_t>({0}));
  p.min_neighbors = 1;
  EXPECT_EQ(remove_radius_outliers(KdTree(pts), p).kept, std::vector<std::uint32_t>({0, 1, 2, 3}));
  p.min_neighbors = 0;  // keeps every point
  EXPECT_EQ(remove_radius_outliers(KdTree(pts), p).kept.size(), 5u);
}

TEST(RadiusOutliers, DuplicatesAreNeighbours) {
  const std::vector<Eigen::Vector3f> pts = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {9, 9, 9}};
  RadiusOutlierParams p;
  p.radius_mm = 0.5;
  p.min_neighbors = 2;
  EXPECT_EQ(remove_radius_outliers(KdTree(pts), p).kept, std::vector<std::uint32_t>({0, 1, 2}));
}

TEST(RadiusOutliers, ThinCableOnAPlaneSurvivesDefaults) {
  // a 3 mm cable seen over ~128 deg at 0.5 mm spacing: its visible strip is only ~7 points wide
  Planted s = planted_scene(0.05f);
  const std::size_t cable_begin = s.points.size();
  const float rc = 1.5f;
  const int arc_steps = 7;
  for (int a = 0; a < 200; ++a)
    for (int t = 0; t < arc_steps; ++t) {
      const float th = -1.117f + t * (2.234f / (arc_steps - 1));  // +-64 deg around +z
      s.points.emplace_back(a * 0.5f, 50.f + rc * std::sin(th), -20.f + rc * std::cos(th));  // below: alone
    }
  const RadiusOutlierResult r = remove_radius_outliers(KdTree(s.points), {});
  std::vector<std::uint32_t> want = iota(s.surface);
  for (std::size_t i = cable_begin; i < s.points.size(); ++i) want.push_back(static_cast<std::uint32_t>(i));
  EXPECT_EQ(r.kept.size(), want.size());
  for (std::size_t i = 0, j = 0; i < want.size() && j < r.kept.size();)
    if (want[i] == r.kept[j]) ++i, ++j;
    else if (want[i] < r.kept[j]) ADD_FAILURE() << "lost " << want[i++];
    else ADD_FAILURE() << "kept " << r.kept[j++];
  EXPECT_EQ(r.kept, want);
}

TEST(RadiusOutliers, ClustersOfUpToSixFlyingPixelsGoWithDefaults) {
  Planted s = planted_scene();
  std::vector<std::uint32_t> want = iota(s.surface);
  for (int size = 1; size <= 6; ++size) {
    const Eigen::Vector3f c(10.f * size, 50.f, -30.f);  // below the plane, far from everything
    for (int i = 0; i < size; ++i) s.points.push_back(c + Eigen::Vector3f(0.3f * i, 0.1f * (i % 2), 0));
  }
  EXPECT_EQ(remove_radius_outliers(KdTree(s.points), {}).kept, want);
}

TEST(RadiusOutliers, NonFiniteAndEmptyClouds) {
  std::vector<Eigen::Vector3f> pts = test::plane_grid(20, 20, 0.5f);
  pts.push_back({std::numeric_limits<float>::quiet_NaN(), 0, 0});
  const RadiusOutlierResult r = remove_radius_outliers(KdTree(pts), {});
  EXPECT_EQ(r.kept, iota(400));
  const RadiusOutlierResult e = remove_radius_outliers(KdTree(std::vector<Eigen::Vector3f>{}), {});
  EXPECT_TRUE(e.kept.empty());
  // all points identical: R = 0, radius 0; duplicates still count as neighbours
  const std::vector<Eigen::Vector3f> same(10, Eigen::Vector3f(1, 1, 1));
  EXPECT_EQ(remove_radius_outliers(KdTree(same), {}).kept.size(), 10u);
}

TEST(RadiusOutliers, SameResultForOneAndTwoThreads) {
  std::vector<Eigen::Vector3f> pts = planted_scene(0.1f, 0.1f).points;
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-10.f, 110.f);
  for (int i = 0; i < 20000; ++i) pts.emplace_back(u(rng), u(rng), u(rng) * 0.3f);
  const KdTree tree(pts);
  RadiusOutlierResult a, b;
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
    a = remove_radius_outliers(tree, {});
  }
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
    b = remove_radius_outliers(tree, {});
  }
  EXPECT_EQ(a.resolution_mm, b.resolution_mm);
  EXPECT_EQ(a.kept, b.kept);
}
