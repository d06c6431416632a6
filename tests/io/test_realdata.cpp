// Real scans nobody here made (shared/realdata/README.txt): point counts and plausible bounds.
#include <gtest/gtest.h>

#include <filesystem>

#include "ewis/io/cloud_io.hpp"
#include "io/io_test_util.hpp"

using namespace ewis;
using namespace io_test;

namespace {

struct Expect {
  std::string file;
  std::size_t points;             // finite points
  std::size_t total;              // points + dropped (0: same as points)
  float max_extent_m;             // largest bounding-box side stays below this (metres)
  std::vector<std::string> fields;
  bool colors = false, normals = false;
};

const CloudFile* read_or_skip(const std::string& rel, CloudFile& storage) {
  const std::string p = realdata(rel);
  if (!std::filesystem::exists(p)) return nullptr;
  storage = read_cloud(p);
  return &storage;
}

void check(const Expect& e) {
  SCOPED_TRACE(e.file);
  CloudFile f;
  if (!read_or_skip(e.file, f)) GTEST_SKIP() << "missing " << realdata(e.file);
  EXPECT_EQ(f.cloud.size(), e.points);
  EXPECT_EQ(f.cloud.size() + f.dropped_nonfinite, e.total ? e.total : e.points);
  if (!e.fields.empty()) {
    EXPECT_EQ(f.fields, e.fields);
  }
  EXPECT_EQ(f.cloud.has_colors(), e.colors);
  EXPECT_EQ(f.cloud.has_normals(), e.normals);
  Eigen::Vector3f lo, hi;
  ASSERT_TRUE(bounds(f.cloud.points, lo, hi));
  const float extent = (hi - lo).maxCoeff();
  EXPECT_GT(extent, 0.0f);
  EXPECT_LT(extent, e.max_extent_m);
}

}  // namespace

TEST(RealData, PclBun0) { check({"pcl/bun0.pcd", 397, 0, 0.3f, {"x", "y", "z", "normal_x", "normal_y", "normal_z", "curvature"}, false, true}); }
TEST(RealData, PclBun4V05) { check({"pcl/bun4.pcd", 361, 0, 0.3f, {"x", "y", "z"}}); }
TEST(RealData, PclChef) { check({"pcl/chef.pcd", 5092, 0, 1.0f, {"x", "y", "z", "normal_x", "normal_y", "normal_z"}, false, true}); }
TEST(RealData, PclMilk) { check({"pcl/milk.pcd", 13704, 0, 1.0f, {"x", "y", "z"}}); }
TEST(RealData, PclRs1) { check({"pcl/rs1.pcd", 289541, 0, 5.0f, {"x", "y", "z"}}); }

TEST(RealData, OrganisedScansWithNans) {
  for (const std::string name :
       {"pcl/table_scene_mug_stereo_textured.pcd", "pcl/milk_cartoon_all_small_clorox.pcd", "pcl/office1.pcd"}) {
    SCOPED_TRACE(name);
    CloudFile f;
    if (!read_or_skip(name, f)) GTEST_SKIP() << "missing " << name;
    EXPECT_EQ(f.width, 640u);
    EXPECT_EQ(f.height, 480u);
    EXPECT_EQ(f.cloud.size() + f.dropped_nonfinite, 307200u);
    EXPECT_GT(f.dropped_nonfinite, 0u);
    EXPECT_GT(f.cloud.size(), 100000u);
    EXPECT_TRUE(f.cloud.has_colors());
    Eigen::Vector3f lo, hi;
    ASSERT_TRUE(bounds(f.cloud.points, lo, hi));
    EXPECT_GT(lo.z(), 0.0f);  // a camera frame: everything in front
    EXPECT_LT(hi.z(), 15.0f);
    // Colours are not all black: the packed rgb(a) was decoded.
    std::size_t lit = 0;
    for (const auto& c : f.cloud.colors) lit += (c[0] | c[1] | c[2]) != 0;
    EXPECT_GT(lit, f.cloud.size() / 2);
  }
}

TEST(RealData, TableSceneMugIsInMetresAndScales) {
  CloudFile f;
  if (!read_or_skip("pcl/table_scene_mug_stereo_textured.pcd", f)) GTEST_SKIP() << "missing";
  const CloudFile mm = read_cloud(realdata("pcl/table_scene_mug_stereo_textured.pcd"), LengthUnit::Metre);
  ASSERT_EQ(mm.cloud.size(), f.cloud.size());
  EXPECT_FLOAT_EQ(mm.cloud.points[100].z(), f.cloud.points[100].z() * 1000.0f);
}

TEST(RealData, StanfordBunnyPlyWithRangeGrid) {
  for (const std::string name : {"bun000", "bun045", "bun090", "bun180", "bun270", "bun315"}) {
    SCOPED_TRACE(name);
    CloudFile f;
    if (!read_or_skip("stanford_bunny/" + name + ".ply", f)) GTEST_SKIP() << "missing";
    EXPECT_GT(f.cloud.size(), 30000u);
    EXPECT_EQ(f.dropped_nonfinite, 0u);
    EXPECT_EQ(f.fields, (std::vector<std::string>{"x", "y", "z"}));
    Eigen::Vector3f lo, hi;
    ASSERT_TRUE(bounds(f.cloud.points, lo, hi));
    EXPECT_LT((hi - lo).maxCoeff(), 0.3f);  // a bunny about 16 cm across
    if (name == "bun000") {
      EXPECT_EQ(f.cloud.size(), 40256u);
    }
  }
}

TEST(RealData, TreesXyzAndTxt) {
  // README.txt's counts for tree1/7/13 are `wc -l`: those files lack a final newline, so each holds one more.
  check({"adtree_trees/tree1.xyz", 11855, 0, 40.0f, {"x", "y", "z"}});
  check({"adtree_trees/tree7.xyz", 15130, 0, 40.0f, {"x", "y", "z"}});
  check({"adtree_trees/tree13.xyz", 6992, 0, 40.0f, {"x", "y", "z"}});
  check({"adtree_trees/tree33.xyz", 10005, 0, 40.0f, {"x", "y", "z"}});
  check({"adtree_trees/Lille_11.xyz", 19337, 0, 40.0f, {"x", "y", "z"}});
  check({"cylsegment_tree/maple_tree_demo.txt", 39598, 0, 40.0f, {"x", "y", "z"}});
  check({"cylsegment_tree/maple_tree_demo_segs.txt", 39598, 0, 40.0f, {"x", "y", "z"}});
}
