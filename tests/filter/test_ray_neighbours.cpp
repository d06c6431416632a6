#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "ewis/filter/ray_neighbours.hpp"

using namespace ewis;

namespace {

// A square grid of points 0.5 mm apart over [-10, 10]^2 in the plane through the origin with normal n (n = z: level).
std::vector<Eigen::Vector3f> plane_grid(const Eigen::Vector3d& n) {
  const Eigen::Vector3d z = n.normalized();
  const Eigen::Vector3d x = z.unitOrthogonal(), y = z.cross(x);
  std::vector<Eigen::Vector3f> pts;
  for (int i = -20; i <= 20; ++i)
    for (int j = -20; j <= 20; ++j) pts.push_back((0.5 * i * x + 0.5 * j * y).cast<float>());
  return pts;
}

}  // namespace

// Seen from 600 mm above: a point of a level plane has its 8 grid neighbours at its range (within 1.5 x 0.5 mm of its
// ray), none in front or behind; a point 2 mm over the plane has none at its range and the plane's points behind it;
// a point of a plane seen at 70 deg has neighbours at its range (along the plane's level lines) and on both sides.
TEST(RayNeighbours, ASurfaceGoesOnAtItsRangeAFloatingPointHasItBehind) {
  const Eigen::Vector3d eye(0, 0, 600);
  RayNeighbourParams p;
  p.lateral_mm = 0.75;
  std::vector<Neighbor> scratch;

  std::vector<Eigen::Vector3f> level = plane_grid(Eigen::Vector3d::UnitZ());
  const std::uint32_t centre = 20 * 41 + 20;
  ASSERT_LT((level[centre] - Eigen::Vector3f::Zero()).norm(), 1e-6f);
  {
    const KdTree tree(level);
    const RayNeighbours on = ray_neighbours(tree, centre, level[centre].cast<double>(), eye, p, scratch);
    EXPECT_EQ(on.same, 8u);
    EXPECT_EQ(on.front, 0u);
    EXPECT_EQ(on.behind, 0u);
    const RayNeighbours over = ray_neighbours(tree, ~0u, Eigen::Vector3d(0.1, 0.1, 2.0), eye, p, scratch);
    EXPECT_EQ(over.same, 0u);
    EXPECT_EQ(over.front, 0u);
    EXPECT_GE(over.behind, 4u);
    p.reach_mm = 1.5;  // the plane is beyond the reach along the ray
    EXPECT_EQ(ray_neighbours(tree, ~0u, Eigen::Vector3d(0.1, 0.1, 2.0), eye, p, scratch).behind, 0u);
    p.reach_mm = 5.0;
  }
  const double tilt = 70.0 * M_PI / 180.0;
  std::vector<Eigen::Vector3f> steep = plane_grid(Eigen::Vector3d(std::sin(tilt), 0.0, std::cos(tilt)));
  const KdTree tree(steep);
  const RayNeighbours s = ray_neighbours(tree, centre, steep[centre].cast<double>(), eye, p, scratch);
  EXPECT_GE(s.same, 2u);
  EXPECT_GE(s.front, 2u);
  EXPECT_GE(s.behind, 2u);
  EXPECT_EQ(s.front, s.behind);  // symmetric about the point
}
