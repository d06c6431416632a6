#include <gtest/gtest.h>

#include "ewis/core/error.hpp"
#include "ewis/io/pose_file.hpp"
#include "io/io_test_util.hpp"

using namespace ewis;
using namespace io_test;

TEST(PoseFile, ParsesSeparatorsAndRoundTripsExactly) {
  const Pose id = parse_pose("1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n", "p");
  EXPECT_TRUE(id.isApprox(Pose::Identity()));
  const Pose t = parse_pose("1,0,0,10, 0,1,0,-20.5\n0\t0\t1\t3e2\r\n0 0 0 1", "p");
  EXPECT_EQ(t.translation(), Eigen::Vector3d(10, -20.5, 300));
  const Pose j = parse_pose("[[1,0,0,1],[0,1,0,2],[0,0,1,3],[0,0,0,1]]", "p");
  EXPECT_EQ(j.translation(), Eigen::Vector3d(1, 2, 3));

  const Pose p = make_pose(Eigen::Vector3d(1, 2, 3).normalized(), 37.5, Eigen::Vector3d(12.25, -7, 1e3));
  const std::string path = tmp_dir() + "/pose.txt";
  write_pose(p, path);
  const Pose q = read_pose(path);
  EXPECT_LT((q.matrix() - p.matrix()).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_EQ(pose_to_text(Pose::Identity()), "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
}

TEST(PoseFile, FewDecimalsAreSnappedToAnExactRotation) {
  // A 30 degree rotation about z, written with 4 decimals.
  const Pose p = parse_pose("0.8660 -0.5000 0 1\n0.5000 0.8660 0 2\n0 0 1 3\n0 0 0 1\n", "p");
  const Eigen::Matrix3d r = p.linear();
  EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
  EXPECT_NEAR(r(1, 0), 0.5, 1e-4);
}

TEST(PoseFile, RejectsNonRigidAndMalformed) {
  const auto bad = [](const std::string& text) { EXPECT_THROW(parse_pose(text, "p"), InputError) << text; };
  bad("");
  bad("1 0 0 0 0 1 0 0 0 0 1 0 0 0 0");        // 15
  bad("1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 0");    // 17
  bad("1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 one");
  bad("2 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1");      // scale
  bad("1 0.1 0 0 0 1 0 0 0 0 1 0 0 0 0 1");    // shear
  bad("-1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1");     // reflection
  bad("1 0 0 0 0 1 0 0 0 0 1 0 0 0 1 1");      // projective last row
  bad("1 0 0 nan 0 1 0 0 0 0 1 0 0 0 0 1");
  bad("1 0 0 inf 0 1 0 0 0 0 1 0 0 0 0 1");
  EXPECT_THROW(read_pose(tmp_dir() + "/no_pose.txt"), InputError);
  EXPECT_THROW(read_pose(tmp_dir()), InputError);
}
