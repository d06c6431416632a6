#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "ewis/filter/pixel_pitch.hpp"
#include "ewis/filter/resolution.hpp"

using namespace ewis;

namespace {

// A depth image of a plane seen from the origin: pixels `pitch_rad` apart in angle (a pinhole camera looking along +z,
// 121 x 121 pixels about its axis: +-3 deg, where the pinhole's pitch is within 0.5 % of its value at the centre), the
// plane through (0, 0, 600) with normal n; each point moved by an isotropic Gaussian `sigma` per axis and, with
// `stacked`, a second point 0.5-3 mm behind it along every fourth pixel's ray (mixed pixels: one ray, two ranges).
std::vector<Eigen::Vector3f> plane_image(const Eigen::Vector3d& n, double pitch_rad, double sigma, bool stacked,
                                         unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  std::uniform_real_distribution<double> behind(0.5, 3.0);
  std::vector<Eigen::Vector3f> pts;
  const double f = 1.0 / pitch_rad;
  for (int i = -60; i <= 60; ++i)
    for (int j = -60; j <= 60; ++j) {
      const Eigen::Vector3d dir = Eigen::Vector3d(i / f, j / f, 1.0).normalized();
      const double t = n.dot(Eigen::Vector3d(0, 0, 600)) / n.dot(dir);
      const Eigen::Vector3d p = t * dir + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      pts.push_back(p.cast<float>());
      if (stacked && (i + 3 * j) % 4 == 0) pts.push_back((p + behind(rng) * dir).cast<float>());
    }
  return pts;
}

}  // namespace

// Pixels 0.5 mm apart at 600 mm (1/1200 rad): the pitch is read within 3 %, level or tilted by 60 deg (where the
// nearest-neighbour spacing stays 0.5 mm along one side and 1 mm along the other), under isotropic noise of 0.15 mm,
// which shortens the nearest-neighbour distance to ~0.4 mm, and with stacks of two points on a quarter of the rays.
TEST(PixelPitch, ReadsTheSensorsPixelsWhateverTheNoiseAcrossTheRaysAndTheTilt) {
  const double pitch = 1.0 / 1200.0;
  const Eigen::Vector3d sensor = Eigen::Vector3d::Zero();
  const Eigen::Vector3d level = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d tilted = Eigen::AngleAxisd(60.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()) * level;
  for (const Eigen::Vector3d& n : {level, tilted})
    for (const double sigma : {0.0, 0.15})
      for (const bool stacked : {false, true}) {
        const std::vector<Eigen::Vector3f> pts = plane_image(n, pitch, sigma, stacked, 7);
        const KdTree tree(pts);
        const double res = spatial_resolution(tree).median_mm;
        const double measured = angular_pixel_pitch_rad(tree, sensor, res);
        EXPECT_NEAR(measured / pitch, 1.0, 0.03) << "tilt " << n.transpose() << ", noise " << sigma << ", stacked "
                                                 << stacked << ", resolution " << res;
        if (sigma > 0 && !stacked && n.z() == 1.0) {
          EXPECT_LT(res, 0.45);  // what the pitch does not follow
        }
      }
}

TEST(PixelPitch, NothingToCountReadsZero) {
  const std::vector<Eigen::Vector3f> none;  // the tree references its points: they outlive it
  const KdTree empty(none);
  EXPECT_EQ(angular_pixel_pitch_rad(empty, Eigen::Vector3d::Zero(), 0.5), 0.0);
  // points too far apart for any disc to hold the minimum: isolated points, no surface
  std::vector<Eigen::Vector3f> sparse;
  for (int i = 0; i < 50; ++i) sparse.emplace_back(10.f * float(i), 0.f, 600.f);
  const KdTree tree(sparse);
  EXPECT_EQ(angular_pixel_pitch_rad(tree, Eigen::Vector3d::Zero(), 0.5), 0.0);
  EXPECT_EQ(angular_pixel_pitch_rad(tree, Eigen::Vector3d::Zero(), 0.0), 0.0);
}
