// FPFH and PCA normals: known answers on analytic shapes, invariance to a rigid motion.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "ewis/register/fpfh.hpp"
#include "ewis/register/point_normals.hpp"
#include "ewis/register/registration_input.hpp"
#include "synthetic_scene.hpp"
#include "test_tmp.hpp"

namespace ewis {
namespace {

TEST(PointNormals, PlaneNormalsTowardViewpoint) {
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) pts.emplace_back(i, j, 0.0f);
  const KdTree tree(pts);
  PointNormalParams p;
  p.viewpoint = Eigen::Vector3d(10, 10, -50);
  std::vector<float> curv;
  const auto n = estimate_point_normals(tree, p, &curv);
  for (std::size_t i = 0; i < n.size(); ++i) {
    EXPECT_NEAR(n[i].z(), -1.0f, 1e-5);
    EXPECT_NEAR(curv[i], 0.0f, 1e-6);
  }
}

TEST(Fpfh, InvariantToRigidMotionAndPartsSumTo100) {
  const Cloud c = test::sample_scene(test::make_scene(), 4.0, 5);
  const Pose T = make_pose(Eigen::Vector3d(1, 2, 3), 40.0, Eigen::Vector3d(100, -50, 20));
  std::vector<Eigen::Vector3f> moved, moved_n;
  for (std::size_t i = 0; i < c.size(); ++i) {
    moved.push_back((T * c.points[i].cast<double>()).cast<float>());
    moved_n.push_back((T.linear() * c.normals[i].cast<double>()).cast<float>());
  }
  const KdTree t1(c.points), t2(moved);
  FpfhParams fp;
  fp.radius_mm = 20.0;
  const auto f1 = compute_fpfh(t1, c.normals, fp);
  const auto f2 = compute_fpfh(t2, moved_n, fp);
  ASSERT_EQ(f1.size(), c.size());
  std::size_t same = 0, nonzero = 0;
  for (std::size_t i = 0; i < f1.size(); ++i) {
    double sum = 0, max_diff = 0;
    for (int j = 0; j < 33; ++j) {
      max_diff = std::max(max_diff, static_cast<double>(std::abs(f1[i][j] - f2[i][j])));
      sum += f1[i][j];
    }
    same += max_diff < 0.5;
    if (sum > 0) {
      ++nonzero;
      EXPECT_NEAR(sum, 600.0, 0.5);  // three parts, each its SPFH (100) + weighted neighbours (100)
    }
  }
  EXPECT_GT(nonzero, f1.size() * 9 / 10);
  // Equal up to round-off, except where exactly antiparallel normals (a plate's two faces) put the angle at
  // +-pi, whose bin then depends on the sign of a rounded zero (as in PCL).
  EXPECT_GT(same, f1.size() * 95 / 100);
}

TEST(RegistrationInput, PlyWithFacesIsAMesh) {
  const std::string dir = ewis::test::own_tmp_dir("register").string();
  const std::string mesh = dir + "/tri.ply", cloud = dir + "/pts.ply";
  std::ofstream(mesh) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                         "0 0 0\n10 0 0\n0 10 0\n3 0 1 2\n";
  std::ofstream(cloud) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                          "property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
  EXPECT_TRUE(is_mesh_file(mesh));
  EXPECT_FALSE(is_mesh_file(cloud));
  EXPECT_TRUE(is_mesh_file("x.obj"));
  EXPECT_FALSE(is_mesh_file("x.pcd"));
  const RegistrationInput m = read_registration_input(mesh);
  EXPECT_TRUE(m.is_mesh);
  // One open triangle: its other side is added (scene/orient_faces.hpp), whichever way it was wound.
  ASSERT_EQ(m.scene.triangles.size(), 2u);
  EXPECT_EQ(m.scene.triangles[1], Eigen::Vector3i(0, 2, 1));
  const RegistrationInput p = read_registration_input(cloud, LengthUnit::Metre);
  EXPECT_FALSE(p.is_mesh);
  ASSERT_EQ(p.cloud.size(), 3u);
  EXPECT_FLOAT_EQ(p.cloud.points[1].x(), 1000.0f);
}

}  // namespace
}  // namespace ewis
