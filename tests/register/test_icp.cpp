// Point-to-plane ICP against the analytic CAD-like scene: known pose, 0.2 mm noise, outliers, 10 deg / 50 mm off.
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <iostream>

#include "ewis/core/error.hpp"
#include "ewis/register/icp.hpp"
#include "synthetic_scene.hpp"

namespace ewis {
namespace {

using test::make_scene;

using test::off_at_scene;
using test::pose_error;
using test::PoseError;

struct Fixture {
  Scene scene = make_scene();
  Cloud target;
  std::unique_ptr<KdTree> tree;
  Fixture() {
    target = test::sample_scene(scene, 1.0, 99);
    tree = std::make_unique<KdTree>(target.points);
  }
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

TEST(Icp, RecoversPoseFromTenDegreesFiftyMm) {
  const auto& f = fixture();
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const test::SimScan sim = test::simulate_scan(make_scene(), seed);
    const Pose init = off_at_scene(sim.camera_to_cad, seed, 10.0, 50.0);
    IcpParams p;
    p.expected_error_mm = 60.0;
    p.final_max_distance_mm = 1.5;
    p.use_source_viewpoint = true;  // the scan is in its sensor's frame
    const RegistrationResult r = align_point_to_plane(sim.scan.points, f.target, *f.tree, init, p);
    const PoseError e = pose_error(r.source_to_target, sim.camera_to_cad);
    SCOPED_TRACE("seed " + std::to_string(seed));
    EXPECT_LT(e.deg, 0.1);
    EXPECT_LT(e.mm, 0.3);
    EXPECT_TRUE(r.converged);
    EXPECT_GT(r.fitness, 0.8);  // 10% outliers, the rest on the surface
    EXPECT_LT(r.rmse_mm, 0.35);
    EXPECT_GT(r.iterations, 0);
  }
}

TEST(Icp, DeterministicForAnyThreadCount) {
  const auto& f = fixture();
  const test::SimScan sim = test::simulate_scan(make_scene(), 7);
  const Pose init = off_at_scene(sim.camera_to_cad, 7, 5.0, 20.0);
  IcpParams p;
  p.expected_error_mm = 30.0;
  p.use_source_viewpoint = true;
  RegistrationResult r1, r2;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    r1 = align_point_to_plane(sim.scan.points, f.target, *f.tree, init, p);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    r2 = align_point_to_plane(sim.scan.points, f.target, *f.tree, init, p);
  }
  EXPECT_TRUE(r1.source_to_target.matrix() == r2.source_to_target.matrix());
  EXPECT_EQ(r1.iterations, r2.iterations);
  EXPECT_EQ(r1.inliers, r2.inliers);
}

// Two passes (coarse, then fine from its pose) give the same poses, iterations and fitness whether the second
// goes on from the first's correspondences (IcpMemory) or starts afresh; a memory of another tree is dropped.
TEST(Icp, MemoryOfThePassBeforeChangesNoAnswer) {
  const auto& f = fixture();
  const test::SimScan sim = test::simulate_scan(make_scene(), 5);
  const Pose init = off_at_scene(sim.camera_to_cad, 5, 3.0, 10.0);
  IcpParams coarse;
  coarse.expected_error_mm = 15.0;
  coarse.final_max_distance_mm = 3.0;
  IcpParams fine;
  fine.initial_max_distance_mm = 3.0;
  fine.final_max_distance_mm = 1.0;
  const RegistrationResult a1 = align_point_to_plane(sim.scan.points, f.target, *f.tree, init, coarse);
  const RegistrationResult a2 = align_point_to_plane(sim.scan.points, f.target, *f.tree, a1.source_to_target, fine);
  IcpMemory memory;
  const Cloud other_target = test::sample_scene(f.scene, 2.0, 5);
  const KdTree other_tree(other_target.points);
  align_point_to_plane(sim.scan.points, other_target, other_tree, init, coarse, {}, {}, &memory);  // learnt elsewhere
  const RegistrationResult b1 = align_point_to_plane(sim.scan.points, f.target, *f.tree, init, coarse, {}, {}, &memory);
  EXPECT_EQ(memory.tree, f.tree.get());
  const RegistrationResult b2 =
      align_point_to_plane(sim.scan.points, f.target, *f.tree, b1.source_to_target, fine, {}, {}, &memory);
  for (const auto& [a, b] : {std::pair{a1, b1}, std::pair{a2, b2}}) {
    EXPECT_TRUE(a.source_to_target.matrix() == b.source_to_target.matrix());
    EXPECT_EQ(a.iterations, b.iterations);
    EXPECT_EQ(a.inliers, b.inliers);
    EXPECT_EQ(a.rmse_mm, b.rmse_mm);
  }
  EXPECT_LT(pose_error(b2.source_to_target, sim.camera_to_cad).mm, 0.3);
}

TEST(Icp, EvaluateReportsFitnessAtTruth) {
  const auto& f = fixture();
  const test::SimScan sim = test::simulate_scan(make_scene(), 3, 0.2, 0.0);
  const RegistrationResult r = evaluate_registration(sim.scan.points, f.target, *f.tree, sim.camera_to_cad, 1.5);
  EXPECT_GT(r.fitness, 0.97);
  EXPECT_NEAR(r.rmse_mm, 0.2, 0.06);
}

TEST(Icp, RejectsTargetWithoutNormals) {
  Cloud t;
  t.points = {Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(1, 0, 0), Eigen::Vector3f(0, 1, 0)};
  const KdTree tree(t.points);
  EXPECT_THROW(align_point_to_plane(t.points, t, tree, Pose::Identity()), InputError);
  const Cloud empty;
  const KdTree et(empty.points);
  EXPECT_THROW(align_point_to_plane(t.points, empty, et, Pose::Identity()), InputError);
}

}  // namespace
}  // namespace ewis
