#include <gtest/gtest.h>

#include "ewis/core/cloud.hpp"
#include "ewis/core/cylinder.hpp"
#include "ewis/core/parallel.hpp"
#include "ewis/core/pose.hpp"

#include <tbb/global_control.h>

using namespace ewis;

TEST(Cloud, SelectKeepsAttributesInOrder) {
  Cloud c;
  for (int i = 0; i < 5; ++i) {
    c.points.emplace_back(float(i), 0, 0);
    c.intensities.push_back(float(10 * i));
  }
  c.scalars.push_back({"q", {0, 1, 2, 3, 4}});
  Cloud s = select(c, {4, 1});
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s.points[0].x(), 4.f);
  EXPECT_EQ(s.intensities[1], 10.f);
  EXPECT_EQ(s.scalars[0].values[0], 4.f);
  EXPECT_TRUE(s.normals.empty());
}

TEST(Pose, LookAtHasCameraAxes) {
  const Pose p = look_at({0, 0, 600}, {0, 0, 0}, Eigen::Vector3d::UnitY());
  // z forward points from the camera to the target
  EXPECT_NEAR((p.linear().col(2) - Eigen::Vector3d(0, 0, -1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(p.linear().determinant(), 1.0, 1e-12);
  // the up hint appears up in the image: -y of the camera
  EXPECT_GT((-p.linear().col(1)).dot(Eigen::Vector3d::UnitY()), 0.99);
}

TEST(Pose, Errors) {
  const Pose a = make_pose({0, 0, 1}, 0, {0, 0, 0});
  const Pose b = make_pose({1, 1, 0}, 3.0, {3, 4, 0});
  EXPECT_NEAR(rotation_error_deg(a, b), 3.0, 1e-9);
  EXPECT_NEAR(translation_error_mm(a, b), 5.0, 1e-12);
}

TEST(Cylinder, Distances) {
  Cylinder c{{0, 0, 0}, {0, 0, 10}, 2};
  EXPECT_NEAR(distance_to_axis(c, {3, 4, 50}), 5.0, 1e-12);
  EXPECT_NEAR(distance_to_segment(c, {0, 0, 13}), 3.0, 1e-12);
}

TEST(Parallel, ReductionIndependentOfThreads) {
  const std::size_t n = 100000;
  auto run = [&](int threads) {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, threads);
    return parallel_reduce_ordered<double>(n, 1000, 0.0,
        [](std::size_t b, std::size_t e) { double s = 0; for (std::size_t i = b; i < e; ++i) s += 1.0 / (1.0 + i); return s; },
        [](double a, double b) { return a + b; });
  };
  const double one = run(1), two = run(2);
  EXPECT_EQ(one, two);  // bit-identical
  EXPECT_NEAR(one, std::log(double(n)) + 0.5772, 1e-4);
}

TEST(Parallel, SelectIsOrdered) {
  auto idx = parallel_select(10000, [](std::size_t i) { return i % 7 == 0; }, 100);
  ASSERT_EQ(idx.size(), 1429u);
  for (std::size_t k = 0; k < idx.size(); ++k) EXPECT_EQ(idx[k], 7 * k);
}

TEST(Cloud, EvenlyStridedAndPick) {
  EXPECT_EQ(ewis::evenly_strided(5, 0), (std::vector<std::uint32_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(ewis::evenly_strided(5, 9), (std::vector<std::uint32_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(ewis::evenly_strided(10, 4), (std::vector<std::uint32_t>{0, 2, 5, 7}));  // floor(i x 2.5)
  EXPECT_TRUE(ewis::evenly_strided(0, 3).empty());
  const std::vector<int> v = {10, 11, 12, 13};
  EXPECT_EQ(ewis::pick(v, {3, 0, 3}), (std::vector<int>{13, 10, 13}));
  EXPECT_TRUE(ewis::pick(std::vector<int>{}, {0, 1}).empty());
}
