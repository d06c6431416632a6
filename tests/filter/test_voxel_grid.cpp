#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <limits>

#include "ewis/core/error.hpp"
#include "ewis/filter/voxel_grid.hpp"
#include "filter/synth.hpp"

using namespace ewis;

namespace {

// 8 x 8 x 8 points at 0.125 + 0.25 i: with 1 mm voxels from the minimum corner, 2 x 2 x 2 voxels of 64 points
// whose centroids are exactly 0.5 or 1.5 on each axis.
Cloud cube_cloud() {
  Cloud c;
  for (int z = 0; z < 8; ++z)
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) {
        c.points.emplace_back(0.125f + 0.25f * x, 0.125f + 0.25f * y, 0.125f + 0.25f * z);
        c.intensities.push_back(float(x));
        c.normals.emplace_back(0, 0, 1);
      }
  return c;
}

}  // namespace

TEST(VoxelGrid, CentroidsExactOnAGridOrderedByKey) {
  const Cloud c = cube_cloud();
  const VoxelGridResult r = voxel_downsample(c, 1.0);
  ASSERT_EQ(r.cloud.size(), 8u);
  ASSERT_EQ(r.representative.size(), 8u);
  for (int v = 0; v < 8; ++v) {
    // key order: x fastest, then y, then z
    const Eigen::Vector3f want(0.5f + (v & 1), 0.5f + ((v >> 1) & 1), 0.5f + ((v >> 2) & 1));
    EXPECT_EQ(r.cloud.points[v], want) << v;
    EXPECT_FLOAT_EQ(r.cloud.intensities[v], (v & 1) ? 5.5f : 1.5f);
    EXPECT_EQ(r.cloud.normals[v], Eigen::Vector3f(0, 0, 1));
    // representative: nearest to the centroid; 8 points tie at the same distance, the smallest index wins
    std::uint32_t best = 0;
    float best_d = std::numeric_limits<float>::infinity();
    for (std::uint32_t i = 0; i < c.size(); ++i) {
      const float d = (c.points[i] - want).squaredNorm();
      if (d < best_d) best_d = d, best = i;
    }
    EXPECT_EQ(r.representative[v], best) << v;
  }
  EXPECT_TRUE(r.cloud.colors.empty());
}

TEST(VoxelGrid, OneVoxelHoldsEverythingAndSinglePointsStay) {
  const Cloud c = cube_cloud();
  const VoxelGridResult big = voxel_downsample(c, 100.0);
  ASSERT_EQ(big.cloud.size(), 1u);
  EXPECT_EQ(big.cloud.points[0], Eigen::Vector3f(1, 1, 1));
  const VoxelGridResult fine = voxel_downsample(c, 0.1);
  EXPECT_EQ(fine.cloud.size(), c.size());
}

TEST(VoxelGrid, NormalsAveragedAndRenormalised) {
  Cloud c;
  c.points = {{0.1f, 0.1f, 0.1f}, {0.2f, 0.2f, 0.2f}};
  c.normals = {{1, 0, 0}, {0, 1, 0}};
  c.colors = {{0, 100, 255}, {10, 101, 255}};
  c.scalars.push_back({"q", {1.f, 2.f}});
  const VoxelGridResult r = voxel_downsample(c, 1.0);
  ASSERT_EQ(r.cloud.size(), 1u);
  EXPECT_NEAR(r.cloud.normals[0].norm(), 1.0f, 1e-6f);
  EXPECT_NEAR(r.cloud.normals[0].x(), std::sqrt(0.5f), 1e-6f);
  EXPECT_EQ(r.cloud.colors[0][0], 5);
  EXPECT_EQ(r.cloud.colors[0][2], 255);
  EXPECT_FLOAT_EQ(r.cloud.scalars[0].values[0], 1.5f);
}

TEST(VoxelGrid, BadSizesThrowInputError) {
  const Cloud c = cube_cloud();
  EXPECT_THROW(voxel_downsample(c, 0.0), InputError);
  EXPECT_THROW(voxel_downsample(c, -1.0), InputError);
  EXPECT_THROW(voxel_downsample(c, std::numeric_limits<double>::quiet_NaN()), InputError);
  Cloud wide;
  wide.points = {{-1e30f, -1e30f, -1e30f}, {1e30f, 1e30f, 1e30f}};
  EXPECT_THROW(voxel_downsample(wide, 1.0), InputError);
  EXPECT_THROW(voxel_downsample(c, 1e-7), InputError);  // 2e7 cells per axis: 8e21 keys
}

TEST(VoxelGrid, EmptyAndNonFinite) {
  EXPECT_EQ(voxel_downsample(Cloud{}, 1.0).cloud.size(), 0u);
  Cloud c;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  c.points = {{nan, 0, 0}, {0.5f, 0.5f, 0.5f}, {0, nan, 1}};
  const VoxelGridResult r = voxel_downsample(c, 1.0);
  ASSERT_EQ(r.cloud.size(), 1u);
  EXPECT_EQ(r.representative[0], 1u);
  Cloud all_nan;
  all_nan.points = {{nan, nan, nan}};
  EXPECT_EQ(voxel_downsample(all_nan, 1.0).cloud.size(), 0u);
}

TEST(VoxelGrid, SameResultForOneAndTwoThreads) {
  Cloud c;
  c.points = test::plane_grid(400, 300, 0.5f, 0.f, 0.2f, 0.3f, 4);
  VoxelGridResult a, b;
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
    a = voxel_downsample(c, 2.0);
  }
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
    b = voxel_downsample(c, 2.0);
  }
  EXPECT_EQ(a.representative, b.representative);
  ASSERT_EQ(a.cloud.size(), b.cloud.size());
  for (std::size_t i = 0; i < a.cloud.size(); ++i) EXPECT_EQ(a.cloud.points[i], b.cloud.points[i]);
  EXPECT_GT(a.cloud.size(), 100u * 75u);  // 200 x 150 mm in 2 mm voxels, plus noise layers
}
