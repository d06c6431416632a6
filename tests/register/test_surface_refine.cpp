// The registration's last step on the CAD's exact surface (surface_refine.hpp), against the analytic CAD-like scene
// with a known pose, 0.2 mm noise and outliers.
#include <gtest/gtest.h>

#include "ewis/register/surface_refine.hpp"
#include "synthetic_scene.hpp"

namespace ewis {
namespace {

using test::off_at_scene;
using test::pose_error;
using test::PoseError;

std::vector<int> rigid_elements(const Scene& s) {
  std::vector<int> r;
  for (int e = 0; e < static_cast<int>(s.elements.size()); ++e)
    if (s.elements[e].name != "cable_A") r.push_back(e);
  return r;
}

TEST(SurfaceRefine, ConvergesFromHalfAMillimetreOff) {
  const Scene cad = test::make_scene();
  const SurfaceIndex surface(cad, rigid_elements(cad));
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const test::SimScan sim = test::simulate_scan(cad, seed, 0.2, 0.1, 1.0);
    SurfaceRefineParams p;
    p.max_distance_mm = 2.0;
    p.max_iterations = 20;
    const RegistrationResult r = refine_on_surface(sim.scan.points, surface, off_at_scene(sim.camera_to_cad, seed, 0.1, 0.5), p);
    const PoseError e = pose_error(r.source_to_target, sim.camera_to_cad);
    EXPECT_LT(e.deg, 0.002);  // measured 0.0002 deg, 0.0006-0.0014 mm
    EXPECT_LT(e.mm, 0.01);
    EXPECT_TRUE(r.converged);
    EXPECT_GT(r.fitness, 0.8);  // the outliers (10 %) and the cable's points find no rigid surface
  }
}

TEST(SurfaceRefine, NothingToMatchLeavesThePose) {
  const Scene cad = test::make_scene();
  const SurfaceIndex surface(cad, rigid_elements(cad));
  Pose far = Pose::Identity();
  far.translation() = Eigen::Vector3d(0, 0, 5000);  // every point 5 m away from the CAD
  const test::SimScan sim = test::simulate_scan(cad, 1);
  const RegistrationResult r = refine_on_surface(sim.scan.points, surface, far);
  EXPECT_EQ(r.inliers, 0u);
  EXPECT_TRUE(r.source_to_target.isApprox(far));
  EXPECT_EQ(refine_on_surface({}, surface, far).inliers, 0u);
}

}  // namespace
}  // namespace ewis
