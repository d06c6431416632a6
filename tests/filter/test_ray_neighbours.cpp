#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
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

// A depth image of the plane through the origin with normal n, seen from `eye` (600 mm over it): one point per pixel,
// the pixels `pitch` apart where the plane z = 0 is (41 x 41), each kept with probability `keep` and moved by an
// isotropic Gaussian `sigma` per axis. `index` gets each kept point's pixel (i, j).
std::vector<Eigen::Vector3f> depth_image(const Eigen::Vector3d& eye, const Eigen::Vector3d& n, double pitch, double keep,
                                         double sigma, unsigned seed, std::vector<Eigen::Vector2i>& index) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution kept(keep);
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<Eigen::Vector3f> pts;
  index.clear();
  for (int i = -20; i <= 20; ++i)
    for (int j = -20; j <= 20; ++j) {
      const Eigen::Vector3d dir = (Eigen::Vector3d(pitch * i, pitch * j, 0.0) - eye).normalized();
      const double t = -n.dot(eye) / n.dot(dir);
      const Eigen::Vector3d e(noise(rng), noise(rng), noise(rng));
      if (!kept(rng)) continue;
      pts.push_back((eye + t * dir + e).cast<float>());
      index.emplace_back(i, j);
    }
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

// The surface the rays around a point saw (seen_surface_at): on a level plane every point lies on it (offset 0, its 8
// neighbours holding the plane); a point 2 mm over the plane does not (the plane 2 mm behind it). Another scanner's
// view of a plane seen at 60 deg, pixels 0.65 mm apart against a resolution of 0.5 mm, a fifth of them lost and 0.2
// mm of noise on every axis (0.4 mm along the rays): most points lie on the surface their neighbours saw, while by
// the count of neighbours at its range (ray_neighbours: fewer than 2 within 1.5 x resolution of its ray, and fewer
// than 2 on one side) a good share would float. The same points moved 2 mm toward the sensor float.
TEST(RayNeighbours, APointOnTheSurfaceItsNeighboursSawEvenSeenAtAGrazingAngle) {
  const Eigen::Vector3d eye(0, 0, 600);
  RaySurfaceParams p;
  p.lateral_mm = 2.5 * 0.5;
  std::vector<Neighbor> scratch;
  {
    const std::vector<Eigen::Vector3f> level = plane_grid(Eigen::Vector3d::UnitZ());
    const std::uint32_t centre = 20 * 41 + 20;
    const KdTree tree(level);
    const RaySurface on = seen_surface_at(tree, centre, level[centre].cast<double>(), eye, p, scratch);
    EXPECT_TRUE(on.on);
    EXPECT_EQ(on.neighbours, 8u);
    EXPECT_EQ(on.inliers, 8u);
    EXPECT_NEAR(on.offset_mm, 0.0, 1e-6);
    const RaySurface over = seen_surface_at(tree, ~0u, Eigen::Vector3d(0.1, 0.1, 2.0), eye, p, scratch);
    EXPECT_FALSE(over.on);
    EXPECT_NEAR(over.offset_mm, 2.0, 0.01);  // the plane behind it
  }
  const double tilt = 60.0 * M_PI / 180.0;
  const Eigen::Vector3d n(std::sin(tilt), 0.0, std::cos(tilt));
  std::vector<Eigen::Vector2i> pixel;
  const std::vector<Eigen::Vector3f> steep = depth_image(eye, n, 0.65, 0.8, 0.2, 11, pixel);
  const KdTree tree(steep);
  RayNeighbourParams count;
  count.lateral_mm = 1.5 * 0.5;
  std::size_t inner = 0, on = 0, floating_by_count = 0, moved_on = 0;
  for (std::uint32_t k = 0; k < steep.size(); ++k) {
    if (pixel[k].cwiseAbs().maxCoeff() > 15) continue;
    ++inner;
    const Eigen::Vector3d x = steep[k].cast<double>();
    on += seen_surface_at(tree, k, x, eye, p, scratch).on;
    const RayNeighbours c = ray_neighbours(tree, k, x, eye, count, scratch);
    floating_by_count += c.same < 2 && std::min(c.front, c.behind) < 2;
    const Eigen::Vector3d moved = x + 2.0 * (eye - x).normalized();
    moved_on += seen_surface_at(tree, k, moved, eye, p, scratch).on;
  }
  ASSERT_GT(inner, 600u);
  EXPECT_GE(double(on), 0.8 * double(inner));  // 0.2 mm across a 60 deg plane: 0.4 mm along the rays
  EXPECT_GE(double(floating_by_count), 0.2 * double(inner)) << "the count kept the grazing surface: no contrast";
  EXPECT_LE(double(moved_on), 0.02 * double(inner));
}
