#include <gtest/gtest.h>

#include <cmath>

#include "ewis/core/error.hpp"
#include "ewis/plan/candidates.hpp"

namespace ewis {
namespace {

TEST(Candidates, TenDegreeStepGives648) {
  CandidateParams p;
  const CandidateGrid g = make_candidates(Eigen::Vector3d(1, 2, 3), p);
  ASSERT_EQ(g.candidates.size(), 648u);
  ASSERT_EQ(g.theta_deg.size(), 36u);
  ASSERT_EQ(g.phi_deg.size(), 18u);
  EXPECT_DOUBLE_EQ(g.theta_deg.front(), 0.0);
  EXPECT_DOUBLE_EQ(g.theta_deg.back(), 350.0);
  EXPECT_DOUBLE_EQ(g.phi_deg.front(), 5.0);
  EXPECT_DOUBLE_EQ(g.phi_deg.back(), 175.0);
  for (const Candidate& c : g.candidates) {
    EXPECT_NEAR((c.position - c.target).norm(), 600.0, 1e-9);
    EXPECT_NEAR((c.target - Eigen::Vector3d(1, 2, 3)).norm(), 0.0, 1e-12);
    // The spherical coordinates of the rule.
    const Eigen::Vector3d d = (c.position - c.target) / 600.0;
    EXPECT_NEAR(std::acos(d.z()) * 180.0 / M_PI, c.phi_deg, 1e-6);
  }
  // Phi-major, theta-minor order.
  EXPECT_DOUBLE_EQ(g.candidates[1].theta_deg, 10.0);
  EXPECT_DOUBLE_EQ(g.candidates[36].phi_deg, 15.0);
}

TEST(Candidates, RangesLimitTheSphere) {
  CandidateParams p;
  p.theta_min_deg = 0, p.theta_max_deg = 90;
  p.phi_min_deg = 30, p.phi_max_deg = 60;
  const CandidateGrid g = make_candidates(Eigen::Vector3d::Zero(), p);
  EXPECT_EQ(g.theta_deg.size(), 10u);  // 0..90 inclusive
  ASSERT_EQ(g.phi_deg.size(), 3u);     // cell centres 35, 45, 55
  EXPECT_DOUBLE_EQ(g.phi_deg[0], 35.0);
  EXPECT_DOUBLE_EQ(g.phi_deg[2], 55.0);
  EXPECT_EQ(g.candidates.size(), 30u);
  p.step_deg = 30;
  p.theta_min_deg = 0, p.theta_max_deg = 360, p.phi_min_deg = 0, p.phi_max_deg = 180;
  EXPECT_EQ(make_candidates(Eigen::Vector3d::Zero(), p).candidates.size(), 12u * 6u);
}

TEST(Candidates, BadRangesAreInputErrors) {
  CandidateParams p;
  p.step_deg = 0;
  EXPECT_THROW(make_candidates(Eigen::Vector3d::Zero(), p), InputError);
  p = {};
  p.phi_max_deg = 200;
  EXPECT_THROW(make_candidates(Eigen::Vector3d::Zero(), p), InputError);
  p = {};
  p.theta_min_deg = 90, p.theta_max_deg = 10;
  EXPECT_THROW(make_candidates(Eigen::Vector3d::Zero(), p), InputError);
  p = {};
  p.step_deg = 1e-4;
  EXPECT_THROW(make_candidates(Eigen::Vector3d::Zero(), p), InputError);
}

TEST(Candidates, RollRuleKeepsWorldZUp) {
  const CandidateGrid g = make_candidates(Eigen::Vector3d(10, -20, 5), CandidateParams{});
  for (const Candidate& c : g.candidates) {
    const Eigen::Matrix3d R = c.camera_to_cad.linear();
    EXPECT_NEAR(R.determinant(), 1.0, 1e-9);
    // z forward: towards the target.
    EXPECT_NEAR(R.col(2).dot((c.target - c.position).normalized()), 1.0, 1e-9);
    EXPECT_NEAR((c.camera_to_cad.translation() - c.position).norm(), 0.0, 1e-9);
    // Image up (-y) is world +z projected: x horizontal, -y has a positive z part.
    EXPECT_NEAR(R.col(0).z(), 0.0, 1e-9);
    EXPECT_GT(-R.col(1).z(), 0.0);
  }
  // At a pole the rule falls back to world +y up.
  const Pose top = candidate_pose(Eigen::Vector3d(0, 0, 600), Eigen::Vector3d::Zero());
  EXPECT_NEAR(-top.linear().col(1).dot(Eigen::Vector3d::UnitY()), 1.0, 1e-9);
  CandidateParams pole;
  pole.phi_min_deg = pole.phi_max_deg = 0;
  const CandidateGrid gp = make_candidates(Eigen::Vector3d::Zero(), pole);
  ASSERT_EQ(gp.phi_deg.size(), 1u);
  EXPECT_DOUBLE_EQ(gp.phi_deg[0], 0.0);
  EXPECT_NEAR(-gp.candidates[0].camera_to_cad.linear().col(1).y(), 1.0, 1e-9);
}

}  // namespace
}  // namespace ewis
