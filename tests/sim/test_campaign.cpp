#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "ewis/core/error.hpp"
#include "ewis/io/cloud_io.hpp"
#include "ewis/io/plan_file.hpp"
#include "ewis/io/pose_file.hpp"
#include "ewis/sim/campaign.hpp"
#include "test_tmp.hpp"

using namespace ewis;
using namespace ewis::sim;
namespace fs = std::filesystem;

namespace {

std::string tmp(const std::string& name) {
  const fs::path p = ewis::test::own_tmp_dir("sim") / name;
  fs::remove_all(p);
  return p.string();
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

SimulateOptions small_options(std::uint64_t seed, DefectKind defect) {
  SimulateOptions o;
  o.scene.seed = seed;
  o.scene.defect = defect;
  o.scene.sensor.width_px = 320;   // a quarter of the Ensenso's resolution keeps the test fast
  o.scene.sensor.height_px = 256;
  return o;
}

void expect_matrix4(const nlohmann::json& m) {
  ASSERT_TRUE(m.is_array());
  ASSERT_EQ(m.size(), 4u);
  for (const auto& row : m) {
    ASSERT_TRUE(row.is_array());
    ASSERT_EQ(row.size(), 4u);
    for (const auto& v : row) ASSERT_TRUE(v.is_number());
  }
}

}  // namespace

TEST(Campaign, SceneFolderHasEveryFileAndTheTruthSchemaFields) {
  const std::string dir = tmp("one");
  const SceneSummary s = write_scene(dir, small_options(3, DefectKind::ForeignObject));
  for (const char* f : {"scene.obj", "plan.json", "scan.ply", "pose.txt", "truth.json", "scan.png"})
    EXPECT_TRUE(fs::exists(fs::path(dir) / f)) << f;
  const nlohmann::json t = nlohmann::json::parse(slurp(dir + "/truth.json"));
  expect_matrix4(t["camera_to_cad"]);
  ASSERT_TRUE(t["cables"].is_array());
  ASSERT_GE(t["cables"].size(), 1u);
  for (const auto& c : t["cables"]) {
    EXPECT_TRUE(c["name"].is_string());
    EXPECT_GT(c["diameter_mm"].get<double>(), 0.0);
    EXPECT_TRUE(c["length_mm"].is_number());
    EXPECT_TRUE(c["min_bend_radius_mm"].is_number() || c["min_bend_radius_mm"].is_null());
    ASSERT_GE(c["centerline"].size(), 2u);
    for (const auto& p : c["centerline"]) ASSERT_EQ(p.size(), 3u);
    // Centreline spacing <= 1 mm.
    const auto& cl = c["centerline"];
    for (std::size_t i = 1; i < cl.size(); ++i) {
      const double dx = cl[i][0].get<double>() - cl[i - 1][0].get<double>();
      const double dy = cl[i][1].get<double>() - cl[i - 1][1].get<double>();
      const double dz = cl[i][2].get<double>() - cl[i - 1][2].get<double>();
      ASSERT_LE(std::sqrt(dx * dx + dy * dy + dz * dz), 1.0 + 1e-3);
    }
  }
  ASSERT_TRUE(t["defects"].is_array());
  ASSERT_GE(t["defects"].size(), 1u);
  for (const auto& d : t["defects"]) {
    EXPECT_EQ(d["kind"], "foreign_object");
    EXPECT_TRUE(d["element"].is_string());
    EXPECT_TRUE(d["with"].is_null());
    EXPECT_TRUE(d["gap_mm"].is_number());
    // the gap's two ends (on the cable's and the object's surfaces) lie gap_mm apart; `seen` says whether the scan
    // measured both there (gap_visibility.hpp)
    ASSERT_EQ(d["ends"].size(), 2u);
    Eigen::Vector3d ends[2];
    for (int k = 0; k < 2; ++k) {
      for (int i = 0; i < 3; ++i) ends[k][i] = d["ends"][k][i].get<double>();
    }
    if (d["gap_mm"].get<double>() > 0) {
      EXPECT_NEAR((ends[1] - ends[0]).norm(), d["gap_mm"].get<double>(), 2e-3);
    }
    EXPECT_TRUE(d["seen"].is_boolean());
  }
  // The other files read back through the project's readers.
  const InspectionPlan plan = read_plan(dir + "/plan.json");
  EXPECT_EQ(plan.sensor.width_px, 320);
  const CloudFile scan = read_cloud(dir + "/scan.ply");
  EXPECT_EQ(scan.cloud.size(), s.points);
  EXPECT_EQ(t["scan"]["points"].get<std::size_t>(), s.points);
  // pose.txt is within the requested perturbation of the true pose.
  const Pose pose = read_pose(dir + "/pose.txt");
  Eigen::Matrix4d truth;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) truth(r, c) = t["camera_to_cad"][r][c].get<double>();
  const Pose tp(truth);
  EXPECT_LE(rotation_error_deg(pose, tp), 5.0 + 1e-6);
  EXPECT_LE(translation_error_mm(pose, tp), 30.0 + 1e-6);
}

TEST(Campaign, SameSeedSameBytes) {
  const std::string a = tmp("same_a"), b = tmp("same_b");
  write_scene(a, small_options(11, DefectKind::Bend));
  write_scene(b, small_options(11, DefectKind::Bend));
  for (const char* f : {"scene.obj", "plan.json", "scan.ply", "pose.txt", "truth.json", "scan.png"})
    EXPECT_EQ(slurp(a + "/" + f), slurp(b + "/" + f)) << f;
}

TEST(Campaign, HalfTheScenesHaveDefects) {
  const std::string dir = tmp("campaign");
  SimulateOptions o = small_options(5, DefectKind::None);
  o.scene.sensor.width_px = 160;
  o.scene.sensor.height_px = 128;
  const auto scenes = write_campaign(dir, 4, o);
  ASSERT_EQ(scenes.size(), 4u);
  int with_defects = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "scene_%03zu", i);
    const nlohmann::json t = nlohmann::json::parse(slurp((fs::path(dir) / name / "truth.json").string()));
    if (!t["defects"].empty()) ++with_defects;
    EXPECT_EQ(t["defects"].empty(), i % 2 == 0) << name;
  }
  EXPECT_EQ(with_defects, 2);
}

TEST(Campaign, ViewpointPoseIsRead) {
  const std::string dir = tmp("vp");
  fs::create_directories(dir);
  std::ofstream(dir + "/viewpoints.json")
      << R"({"element":"cable_A","candidates":2,"best":[{"rank":1,"camera_to_cad":[[1,0,0,0],[0,-1,0,0],[0,0,-1,600],[0,0,0,1]]},)"
      << R"({"rank":2,"camera_to_cad":[[1,0,0,5],[0,-1,0,0],[0,0,-1,600],[0,0,0,1]]}]})";
  const Pose p = read_viewpoint_pose(dir + "/viewpoints.json", 2);
  EXPECT_DOUBLE_EQ(p.translation().x(), 5.0);
  EXPECT_THROW(read_viewpoint_pose(dir + "/viewpoints.json", 3), InputError);
  EXPECT_THROW(read_viewpoint_pose(dir + "/missing.json", 1), InputError);
}
