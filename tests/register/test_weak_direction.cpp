// A pose the scene hardly fixes along one direction: found by its weakest direction of translation and the fitness
// probed along it (weak_direction.hpp).
#include <gtest/gtest.h>

#include "ewis/register/weak_direction.hpp"

namespace ewis {
namespace {

// CAD samples at 1 mm: a 200 x 200 mm plate (z = 0, normals +z) with a block of 40 x 10 x 10 mm on it, long
// along x: its top and its four sides (normals outward). Along x only the block's two 10 x 10 mm ends fix a pose.
Cloud plate_with_block() {
  Cloud c;
  auto add = [&](double x, double y, double z, float nx, float ny, float nz) {
    c.points.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
    c.normals.emplace_back(nx, ny, nz);
  };
  for (int i = -100; i <= 100; ++i)
    for (int j = -100; j <= 100; ++j)
      if (!(std::abs(i) < 20 && std::abs(j) < 5)) add(i, j, 0.0, 0, 0, 1);
  for (int i = -20; i <= 20; ++i)
    for (int j = -5; j <= 5; ++j) add(i, j, 10.0, 0, 0, 1);
  for (int k = 0; k < 10; ++k) {
    for (int i = -20; i <= 20; ++i) {
      add(i, -5, k, 0, -1, 0);
      add(i, 5, k, 0, 1, 0);
    }
    for (int j = -5; j <= 5; ++j) {
      add(-20, j, k, -1, 0, 0);
      add(20, j, k, 1, 0, 0);
    }
  }
  return c;
}

std::vector<std::uint32_t> all_of(std::size_t n) {
  std::vector<std::uint32_t> idx(n);
  for (std::size_t i = 0; i < n; ++i) idx[i] = static_cast<std::uint32_t>(i);
  return idx;
}

TEST(WeakDirection, APoseSlidAlongAPlateIsFoundAgainByItsBlocksEnds) {
  const Cloud cad = plate_with_block();
  const KdTree tree(cad.points);
  const std::vector<Eigen::Vector3f>& scan = cad.points;  // the scan: the CAD's own samples
  const std::vector<std::uint32_t> idx = all_of(scan.size());
  Pose slid = Pose::Identity();
  slid.translation() = Eigen::Vector3d(8.0, 0.0, 0.0);  // beyond a fine pass's reach of the block's ends

  const WeakDirection weak = weakest_translation(scan, idx, cad, tree, slid, 1.6);
  EXPECT_GT(std::abs(weak.direction.x()), 0.99);
  EXPECT_LT(weak.ratio, 0.01);
  const WeakDirectionParams params;
  const double offset = best_offset_along(scan, idx, cad, tree, slid, weak.direction, 1.6, params);
  // Back to within a step of the true pose: 8 - 7.5 = 0.5 mm (the ends match again within 1.6 mm).
  EXPECT_NEAR(8.0 + offset * weak.direction.x(), 0.0, 0.5 * params.step_mm);

  // At the true pose the ends fix it: no weak direction along x, and no offset beats it.
  const WeakDirection at_truth = weakest_translation(scan, idx, cad, tree, Pose::Identity(), 1.6);
  EXPECT_GT(at_truth.ratio, weak.ratio);
  EXPECT_EQ(best_offset_along(scan, idx, cad, tree, Pose::Identity(), Eigen::Vector3d::UnitX(), 1.6, params), 0.0);
}

TEST(WeakDirection, AFlatDirectionWithNothingToFindGivesNoOffset) {
  // A plate alone, seen within its edges: every offset along it fits as well, none by min_gain more.
  Cloud plate;
  for (int i = -100; i <= 100; ++i)
    for (int j = -100; j <= 100; ++j) {
      plate.points.emplace_back(static_cast<float>(i), static_cast<float>(j), 0.0f);
      plate.normals.emplace_back(0.0f, 0.0f, 1.0f);
    }
  const KdTree tree(plate.points);
  std::vector<Eigen::Vector3f> scan;
  for (int i = -50; i <= 50; ++i)
    for (int j = -50; j <= 50; ++j) scan.emplace_back(static_cast<float>(i) + 0.5f, static_cast<float>(j), 0.0f);
  const std::vector<std::uint32_t> idx = all_of(scan.size());
  const WeakDirection weak = weakest_translation(scan, idx, plate, tree, Pose::Identity(), 1.6);
  EXPECT_LT(weak.ratio, 1e-9);
  EXPECT_EQ(best_offset_along(scan, idx, plate, tree, Pose::Identity(), weak.direction, 1.6, WeakDirectionParams{}), 0.0);
}

}  // namespace
}  // namespace ewis
