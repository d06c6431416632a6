// trace_tube on real scans (skipped when the files are absent): laser-scanned trees followed from the trunk
// base to the first fork, and the PCL mug (through the CLI, which reads its compressed PCD).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <cmath>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "ewis/filter/outlier_removal.hpp"
#include "ewis/search/kdtree.hpp"
#include "ewis/tubes/trace.hpp"
#include "test_tmp.hpp"

namespace {

namespace fs = std::filesystem;
using Eigen::Vector3d;

bool read_xyz_m(const std::string& path, ewis::Cloud& cloud) {
  std::ifstream in(path);
  if (!in) return false;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    double x, y, z;
    if (ss >> x >> y >> z) cloud.points.emplace_back(float(x * 1000), float(y * 1000), float(z * 1000));
  }
  return !cloud.empty();
}

// ASCII PLY for a person to look at: the tube's points red, the others grey.
void write_coloured_ply(const std::string& path, const ewis::Cloud& cloud, const std::vector<std::uint32_t>& tube) {
  std::vector<char> on(cloud.size(), 0);
  for (std::uint32_t i : tube) on[i] = 1;
  std::ofstream out(path);
  out << "ply\nformat ascii 1.0\nelement vertex " << cloud.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
         "property uchar blue\nend_header\n";
  for (std::size_t i = 0; i < cloud.size(); ++i)
    out << cloud.points[i].x() << ' ' << cloud.points[i].y() << ' ' << cloud.points[i].z() << (on[i] ? " 230 25 75\n" : " 128 128 128\n");
}

// How the seed at the trunk's base is found: the segmented AdTree trees start at the trunk, so the middle of
// the slice 0.3-0.6 m above the lowest point is on it; the maple scan includes the ground and undergrowth, so
// there the seed is the centroid of the densest 0.3 m column 1-4 m above the lowest point (a trunk is the
// tallest dense vertical run of points near the ground).
enum class SeedRule { BaseSlice, DensestColumn };
struct TreeCase {
  const char* file;  // under realdata/: x y z in metres (extra columns ignored)
  SeedRule seed;
};

Vector3d trunk_seed(const ewis::Cloud& cloud, SeedRule rule) {
  float zmin = 1e30f;
  for (const auto& p : cloud.points) zmin = std::min(zmin, p.z());
  const bool slice = rule == SeedRule::BaseSlice;
  const double z0 = zmin + (slice ? 300.0 : 1000.0), z1 = zmin + (slice ? 600.0 : 4000.0);
  std::map<std::pair<long, long>, std::pair<Vector3d, int>> columns;  // 300 mm cells in x-y
  for (const auto& p : cloud.points) {
    if (p.z() < z0 || p.z() > z1) continue;
    const auto key = slice ? std::make_pair(0L, 0L)
                           : std::make_pair(long(std::floor(p.x() / 300.0)), long(std::floor(p.y() / 300.0)));
    auto& c = columns.try_emplace(key, Vector3d::Zero(), 0).first->second;
    c.first += p.cast<double>();
    ++c.second;
  }
  std::pair<Vector3d, int> best{Vector3d::Zero(), 0};
  for (const auto& [key, c] : columns)
    if (c.second > best.second) best = c;
  return best.second > 10 ? Vector3d(best.first / best.second) : Vector3d::Constant(std::nan(""));
}

class TreeTrunk : public ::testing::TestWithParam<TreeCase> {};

TEST_P(TreeTrunk, FollowedFromTheBaseUpToTheFirstFork) {
  const std::string file = GetParam().file;
  const std::string name = std::filesystem::path(file).stem().string();
  const std::string path = std::string(EWIS_REALDATA_DIR) + "/" + file;
  ewis::Cloud raw;
  if (!read_xyz_m(path, raw)) GTEST_SKIP() << path << " not available";
  const ewis::KdTree raw_tree(raw.points);
  const ewis::Cloud cloud = ewis::select(raw, ewis::remove_radius_outliers(raw_tree, {}).kept);
  const ewis::KdTree tree(cloud.points);
  const Vector3d seed = trunk_seed(cloud, GetParam().seed);
  ASSERT_TRUE(seed.allFinite()) << "no points where the trunk's base should be";
  // the ground at the trunk: the lowest point within 1.5 m of the seed across (terrain is not flat)
  double zmin = 1e30;
  for (const auto& p : cloud.points)
    if ((p.cast<double>() - seed).head<2>().norm() < 1500.0) zmin = std::min(zmin, double(p.z()));
  const ewis::TubeTrace t = ewis::trace_tube(cloud, tree, seed, {});
  ASSERT_TRUE(t.found) << name;
  const Vector3d a = t.centerline.front(), b = t.centerline.back();
  std::printf("[tree %s] radius %.1f mm, length %.0f mm, %zu sub-cables, %zu gaps, z %.0f..%.0f (ground %.0f), ends %s / %s\n",
              name.c_str(), t.radius_mm, t.length_mm, t.segments.size(), t.gaps.size(), std::min(a.z(), b.z()),
              std::max(a.z(), b.z()), double(zmin), t.end_reason_front.c_str(), t.end_reason_back.c_str());
  EXPECT_GT(t.radius_mm, 30.0);
  EXPECT_LT(t.radius_mm, 500.0);
  EXPECT_GT(t.length_mm, 500.0);
  // a trunk: mostly upright, from near the ground (the data under the maple's undergrowth start ~0.5 m up)
  EXPECT_GT(std::abs(b.z() - a.z()) / (b - a).norm(), 0.7);
  EXPECT_LT(std::min(a.z(), b.z()), zmin + 700.0);
  const fs::path dir = ewis::test::own_tmp_dir("tubes");
  write_coloured_ply((dir / (name + "_trunk.ply")).string(), cloud, t.points);
}

INSTANTIATE_TEST_SUITE_P(RealTrees, TreeTrunk,
                         ::testing::Values(TreeCase{"adtree_trees/tree1.xyz", SeedRule::BaseSlice},
                                           TreeCase{"adtree_trees/tree7.xyz", SeedRule::BaseSlice},
                                           TreeCase{"adtree_trees/tree13.xyz", SeedRule::BaseSlice},
                                           TreeCase{"adtree_trees/tree33.xyz", SeedRule::BaseSlice},
                                           TreeCase{"adtree_trees/Lille_11.xyz", SeedRule::BaseSlice},
                                           TreeCase{"cylsegment_tree/maple_tree_demo.txt", SeedRule::DensestColumn}));

// The mug of PCL's cylinder-segmentation tutorial: body radius 39.6 mm (+- 2). Its PCD is LZF-compressed,
// so this goes through the CLI (skipped when the binary has not been built).
TEST(MugRealData, BodyRadiusThroughTheCli) {
  const std::string scan = std::string(EWIS_REALDATA_DIR) + "/pcl/table_scene_mug_stereo_textured.pcd";
  if (!fs::exists(scan)) GTEST_SKIP() << scan << " not available";
  const fs::path bin = fs::path(EWIS_TEST_TMP) / ".." / "bin" / "ewis";
  if (!fs::exists(bin)) GTEST_SKIP() << bin << " not built";
  const fs::path out = ewis::test::own_tmp_dir("tubes") / "mug";
  fs::create_directories(out);
  // seed: on the body, facing the sensor, from PCL's reference axis (point (45.2, 92.5, 790.2) mm, axis
  // (0.205, -0.722, -0.661)) moved by the radius towards the camera
  const std::string cmd = bin.string() + " tubes -q --scan " + scan + " --scan-units m --seed 33.3,116.1,760.7 --out " +
                          out.string() + " --threads 1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream in(out / "tubes.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  ASSERT_EQ(j["tubes"].size(), 1u);
  const auto& t = j["tubes"][0];
  ASSERT_TRUE(t["found"].get<bool>());
  const double r = t["radius_mm"].get<double>();
  std::printf("[mug] radius %.2f mm, length %.1f mm, %zu points\n", r, t["length_mm"].get<double>(),
              t["points"].get<std::size_t>());
  EXPECT_NEAR(r, 39.6, 2.0);
  EXPECT_GT(t["points"].get<int>(), 3000);
  EXPECT_TRUE(fs::exists(out / "tubes.ply"));
}

}  // namespace
