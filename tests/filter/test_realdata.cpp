// Robustness on measured data nobody here made (README.txt of the realdata folder): a laser-scanned tree.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <fstream>
#include <string>

#include "ewis/filter/euclidean_clusters.hpp"
#include "ewis/filter/normals.hpp"
#include "ewis/filter/outlier_removal.hpp"
#include "ewis/filter/resolution.hpp"
#include "ewis/filter/voxel_grid.hpp"

using namespace ewis;

namespace {

// ASCII "x y z [...]" in metres, converted to mm.
std::vector<Eigen::Vector3f> read_xyz_mm(const std::string& path) {
  std::vector<Eigen::Vector3f> pts;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    float x, y, z;
    if (std::sscanf(line.c_str(), "%f %f %f", &x, &y, &z) == 3) pts.emplace_back(1000.f * x, 1000.f * y, 1000.f * z);
  }
  return pts;
}

}  // namespace

TEST(RealData, MapleTreeScanFiltersSanelyAndDeterministically) {
  const std::string path = std::string(EWIS_REALDATA_DIR) + "/cylsegment_tree/maple_tree_demo.txt";
  const auto pts = read_xyz_mm(path);
  if (pts.empty()) GTEST_SKIP() << "missing " << path;
  ASSERT_EQ(pts.size(), 39598u);
  const KdTree tree(pts);
  const ResolutionResult res = spatial_resolution(tree);
  EXPECT_GT(res.median_mm, 0.0);
  EXPECT_LE(res.median_mm, res.mean_mm * 1.5);
  EXPECT_NEAR(res.median_mm, 26.6, 1.0);  // this demo file is a thinned scan: ~27 mm spacing (measured)

  RadiusOutlierResult a, b;
  ClusterResult ca, cb;
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
    a = remove_radius_outliers(tree, {});
    ca = euclidean_clusters(tree, a.kept, 3.0 * res.median_mm, 10);
  }
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
    b = remove_radius_outliers(tree, {});
    cb = euclidean_clusters(tree, b.kept, 3.0 * res.median_mm, 10);
  }
  EXPECT_EQ(a.kept, b.kept);
  EXPECT_EQ(ca.clusters, cb.clusters);
  // a TLS scan of one tree: the filter keeps most points (it drops sparse twigs), and the trunk with the
  // main branches forms the largest cluster
  EXPECT_GT(a.kept.size(), pts.size() * 7 / 10);
  ASSERT_FALSE(ca.clusters.empty());
  EXPECT_GT(ca.clusters[0].size(), a.kept.size() / 5);

  Cloud c;
  c.points = pts;
  const VoxelGridResult v = voxel_downsample(c, 100.0);
  EXPECT_GT(v.cloud.size(), 100u);
  EXPECT_LT(v.cloud.size(), pts.size());
  const auto normals = estimate_normals(tree, NormalParams{});
  std::size_t defined = 0;
  for (const auto& n : normals) defined += n.squaredNorm() > 0.5f;
  EXPECT_GT(defined, pts.size() * 9 / 10);
}
