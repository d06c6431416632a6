// Bends scanned by the virtual sensor, through the whole inspection.
// A C-bend (as on seed 3030's scene_050): an arc of 107 mm turning 24 deg, 10 mm straight, an arc of 88 mm turning
// 103 deg the same way, on a 9.2 mm cable. Before the trace left out the points its tube hides from the sensor, a
// candidate's window across both arcs put a 2 mm "leg" on the second arc (FilletRefineParams::min_seen_leg_*) and
// its smooth tube overshot at the second arc's onset: 81.6 mm on one scan of three without that rule (its analytic
// test: FilletRefine.AnArcGoingOnPastALegIsToldFromTheNextBend). Since, a candidate inside the long second arc whose
// fillet stopped at its iteration limit left its circle windows' figure standing (84.56 on seed 16); its settled fit
// (FilletRefineParams::settle_unconverged) reads the arc. Known limit (docs/inspect.md): on seed 4 of this scene the
// smooth tube over a window holding the first arc's end, the straight and the second arc's onset overshoots there
// (82.35, -6.4 %); the other 23 seeds of 1-24 read within 0.8 %.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "ewis/inspect/pipeline.hpp"
#include "ewis/raycast/raycaster.hpp"
#include "ewis/scene/primitives.hpp"
#include "ewis/sim/sensor.hpp"
#include "paths.hpp"
#include "plan_rules.hpp"

using namespace ewis;

namespace {

struct Bend {
  Scene scene;
  InspectionPlan plan;
  Cloud scan;
  Pose camera_to_cad;
};

std::vector<Eigen::Vector3d> c_bend() {
  test::Turtle t;
  t.pos = {-200, -60, 30};
  t.points = {t.pos};
  t.step = 0.5;
  t.straight(60);
  t.arc(107.0, 24.0, -Eigen::Vector3d::UnitY());
  t.straight(10);
  t.arc(88.0, 103.0, t.dir.cross(Eigen::Vector3d::UnitZ()));
  t.straight(40);
  return t.points;
}

Bend make_bend(const std::vector<Eigen::Vector3d>& axis, double r, std::uint64_t seed, double mixed_share = 0.02) {
  Bend b;
  const Mesh tube = make_tube(axis, r, 32);
  add_element(b.scene, "cable_A", tube.vertices, tube.triangles);
  const Mesh plate = make_box({-300, -250, -5}, {300, 250, 0});
  add_element(b.scene, "plate", plate.vertices, plate.triangles);
  b.plan.elements.push_back(test::cable_rule("cable_A", 2 * r, 40.0, 3.0));
  b.camera_to_cad = look_at({-150, 120, 600}, {-60, 0, 30}, Eigen::Vector3d(0.3, 1, 0).normalized());
  const Raycaster caster(b.scene);
  sim::SensorParams sp;
  sp.seed = seed;
  sp.sigma600_mm = 0.3;
  // The sensor model's mixed pixels are a share of the whole cloud, spread over the scene's depth edges: a lone
  // cable over a plate would get them all, a veil of ~250 points per mm of its silhouette (a campaign scene has
  // many more edges). A real sensor gives one depth per pixel. At the default share: ScannedBend.AVeil...
  sp.mixed_share = mixed_share;
  b.scan = sim::scan(caster, Camera{}, b.camera_to_cad, sp).cloud;
  return b;
}

double min_radius(const Bend& b, const FilletRefineParams& fillet = {}) {
  InspectParams p;
  p.register_scan = false;  // the true pose
  p.fillet = fillet;
  const InspectionResult res = inspect(b.scene, b.plan, b.scan, b.camera_to_cad, p);
  EXPECT_EQ(res.cables.size(), 1u);
  if (res.cables.empty() || !res.cables[0].found || !res.cables[0].min_bend_radius_mm) return 0.0;
  return *res.cables[0].min_bend_radius_mm;
}

}  // namespace

TEST(ScannedBend, ACBendReadsItsSecondArc) {
  const double truth = 88.0, d = 9.2;
  for (std::uint64_t seed : {1, 2, 3, 16}) {
    const Bend b = make_bend(c_bend(), 0.5 * d, seed);
    EXPECT_NEAR(min_radius(b), truth, 0.02 * truth) << "seed " << seed;
    if (seed == 16) {
      // Inside the long arc the fillet's legs lie beyond the window and its vertex has a flat direction. With the
      // Jacobian by forward differences of the distances the fit wandered along it until its iteration limit, and
      // only a second run (FilletRefineParams::settle_unconverged) kept its reading from the circle windows' 84.56;
      // with the closest points' derivatives the flat direction has no gradient and the fit converges by itself.
      FilletRefineParams unsettled;
      unsettled.settle_unconverged = false;
      EXPECT_NEAR(min_radius(b, unsettled), truth, 0.02 * truth);
    }
  }
}

// At the sensor model's default mixed share a veil of ~250 points per mm hangs from the lone cable's silhouette
// towards the plate. The trace's check for "a plane going on just outside the surface" counted it and broke the
// trace (seeds 1-3: 7, 6 and 8 gaps, 4, 1 and 1 runs); points the tube itself hides from the sensor are no such
// surface (TubeParams::hidden_check).
TEST(ScannedBend, AVeilHangingFromTheSilhouetteDoesNotBreakTheTrace) {
  const std::vector<Eigen::Vector3d> axis = c_bend();
  double length = 0;
  for (std::size_t k = 1; k < axis.size(); ++k) length += (axis[k] - axis[k - 1]).norm();
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const Bend b = make_bend(axis, 4.6, seed, sim::SensorParams{}.mixed_share);
    InspectParams p;
    p.register_scan = false;
    const InspectionResult res = inspect(b.scene, b.plan, b.scan, b.camera_to_cad, p);
    ASSERT_EQ(res.cables.size(), 1u);
    const CableInspection& c = res.cables[0];
    ASSERT_TRUE(c.found) << "seed " << seed;
    std::size_t gaps = 0;
    for (const TubeTrace& r : c.runs) gaps += r.gaps.size();
    EXPECT_EQ(c.runs.size(), 1u) << "seed " << seed;
    EXPECT_LE(gaps, 1u) << "seed " << seed;
    EXPECT_GT(c.length_mm, 0.95 * length) << "seed " << seed;
  }
}
