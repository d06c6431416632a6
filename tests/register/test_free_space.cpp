// Free space seen by the sensor: CAD faces in front of what the sensor measured contradict a pose.
#include <gtest/gtest.h>

#include <random>

#include "ewis/register/free_space.hpp"

namespace ewis {
namespace {

// In the sensor frame (at the origin, looking along +z): a floor at depth 700 with 0.5 mm noise and 5 % of
// outliers spread through the view (what outlier removal leaves), and in front of it a 200 x 200 mm plate at
// depth 600.
std::vector<Eigen::Vector3f> plate_over_floor(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<float> noise(0.0f, 0.5f);
  std::vector<Eigen::Vector3f> pts;
  for (int i = -300; i <= 300; ++i)
    for (int j = -300; j <= 300; ++j) {
      const Eigen::Vector3f ray(0.001f * static_cast<float>(i), 0.001f * static_cast<float>(j), 1.0f);
      const Eigen::Vector3f on_plate = ray * 600.0f;
      const bool plate = std::abs(on_plate.x()) <= 100.0f && std::abs(on_plate.y()) <= 100.0f;
      pts.push_back(ray * ((plate ? 600.0f : 700.0f) + noise(rng)));
    }
  std::uniform_real_distribution<float> u(-0.3f, 0.3f), z(200.0f, 900.0f);
  const std::size_t outliers = pts.size() / 20;
  for (std::size_t k = 0; k < outliers; ++k) {
    const float d = z(rng);
    pts.emplace_back(u(rng) * d, u(rng) * d, d);
  }
  return pts;
}

// CAD samples (in the CAD frame = the sensor frame here) of a square at depth `depth`, normals toward the sensor.
Cloud square_at(double depth, double half_mm) {
  Cloud c;
  for (double x = -half_mm; x <= half_mm; x += 2.0)
    for (double y = -half_mm; y <= half_mm; y += 2.0) {
      c.points.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(depth));
      c.normals.emplace_back(0.0f, 0.0f, -1.0f);
    }
  return c;
}

TEST(FreeSpace, FacesInFrontOfTheMeasuredSurfaceCount) {
  const RangeBins bins = bin_scan_depths(plate_over_floor(3));
  ASSERT_GT(bins.bin, 0.0);
  const Pose identity = Pose::Identity();
  // The plate where it was measured, and the floor beside it: nothing in front.
  EXPECT_LT(count_in_front(bins, square_at(600.0, 90.0), identity, 10.0).fraction(), 0.01);
  EXPECT_LT(count_in_front(bins, square_at(700.0, 150.0), identity, 10.0).fraction(), 0.01);
  // Behind the plate (a hidden face): still nothing in front.
  EXPECT_LT(count_in_front(bins, square_at(650.0, 90.0), identity, 10.0).fraction(), 0.01);
  // A block 50 mm in front of the floor beside the plate: the sensor saw the floor through it.
  Cloud block = square_at(650.0, 40.0);
  for (Eigen::Vector3f& p : block.points) p.x() += 150.0f;
  const FreeSpaceCount c = count_in_front(bins, block, identity, 10.0);
  EXPECT_GT(c.seen, 1000u);
  EXPECT_GT(c.fraction(), 0.8);  // bins where two outliers lie in front of it are hidden
  // The same faces turned away from the sensor are not checked.
  for (Eigen::Vector3f& n : block.normals) n = -n;
  EXPECT_EQ(count_in_front(bins, block, identity, 10.0).seen, 0u);
  // Moved by a pose: the plate's samples 40 mm nearer the sensor are in front of it.
  Pose nearer = Pose::Identity();
  nearer.translation() = Eigen::Vector3d(0.0, 0.0, 40.0);  // scan_to_cad: the CAD is 40 mm deeper than the scan
  EXPECT_GT(count_in_front(bins, square_at(600.0, 90.0), nearer, 10.0).fraction(), 0.8);
}

TEST(FreeSpace, NoImageForAScanNotInItsSensorsFrame) {
  std::vector<Eigen::Vector3f> pts = plate_over_floor(4);
  for (Eigen::Vector3f& p : pts) p.z() -= 650.0f;  // the origin inside the scene: half the points behind it
  EXPECT_EQ(bin_scan_depths(pts).bin, 0.0);
  EXPECT_EQ(count_in_front(bin_scan_depths(pts), square_at(0.0, 50.0), Pose::Identity(), 10.0).seen, 0u);
}

TEST(FreeSpace, ALineScannersProfileMakesASmallImage) {
  // One profile of a line scanner: every ray in the plane y = 0 (the angular box has no area). The image must stay
  // about as large as the points are many, not one bin per 1e-8 of angle.
  std::vector<Eigen::Vector3f> pts;
  for (int i = -5000; i <= 5000; ++i) pts.emplace_back(0.06f * static_cast<float>(i), 0.0f, 650.0f);
  pts.emplace_back(0.0f, 0.0f, 700.0f);  // one point 50 mm behind another on its ray
  const RangeBins bins = bin_depths(pts, 4.0);
  ASSERT_GT(bins.bin, 0.0);
  EXPECT_LE(static_cast<std::size_t>(bins.width) * static_cast<std::size_t>(bins.height), pts.size());
  const std::ptrdiff_t k = range_bin(bins, Eigen::Vector3d(0.0, 0.0, 700.0));
  ASSERT_GE(k, 0);
  EXPECT_NEAR(bins.nearest_mm[static_cast<std::size_t>(k)], 650.0f, 1e-3f);  // the second-nearest of its bin
  EXPECT_EQ(range_bin(bins, Eigen::Vector3d(0.0, 0.0, -700.0)), -1);         // behind the sensor
  EXPECT_EQ(range_bin(bins, Eigen::Vector3d(1000.0, 0.0, 650.0)), -1);       // outside the image
}

}  // namespace
}  // namespace ewis
