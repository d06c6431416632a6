// Bends scanned by the virtual sensor, through the whole inspection.
// A C-bend (as on seed 3030's scene_050): an arc of 107 mm turning 24 deg, 10 mm straight, an arc of 88 mm turning
// 103 deg the same way, on a 9.2 mm cable. A candidate's window across both arcs put a 2 mm "leg" on the second arc
// (FilletRefineParams::min_seen_leg_*), and the smooth tube over the same candidate, across the second arc's onset,
// overshot there (the quartic cannot follow the curvature's step): 81.6 mm on one scan of three, -7.3 %. With the
// candidate refused as a whole the second arc's own fit stands.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "ewis/inspect/pipeline.hpp"
#include "ewis/raycast/raycaster.hpp"
#include "ewis/scene/primitives.hpp"
#include "ewis/sim/sensor.hpp"
#include "paths.hpp"

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

Bend make_bend(const std::vector<Eigen::Vector3d>& axis, double r, std::uint64_t seed) {
  Bend b;
  const Mesh tube = make_tube(axis, r, 32);
  add_element(b.scene, "cable_A", tube.vertices, tube.triangles);
  const Mesh plate = make_box({-300, -250, -5}, {300, 250, 0});
  add_element(b.scene, "plate", plate.vertices, plate.triangles);
  PlanElement e;
  e.name = "cable_A";
  e.kind = ElementKind::Cable;
  e.diameter_mm = 2 * r;
  e.min_bend_radius_mm = 40.0;
  e.clearance_mm = 3.0;
  b.plan.elements.push_back(e);
  b.camera_to_cad = look_at({-150, 120, 600}, {-60, 0, 30}, Eigen::Vector3d(0.3, 1, 0).normalized());
  const Raycaster caster(b.scene);
  sim::SensorParams sp;
  sp.seed = seed;
  sp.sigma600_mm = 0.3;
  // The sensor model's mixed pixels are a share of the whole cloud, spread over the scene's depth edges: a lone
  // cable over a plate would get them all, a veil of ~250 points per mm of its silhouette (a campaign scene has
  // many more edges). A real sensor gives one depth per pixel.
  sp.mixed_share = 0.02;
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

TEST(ScannedBend, AWindowCuttingAnArcIsNoReading) {
  const double truth = 88.0, d = 9.2;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const Bend b = make_bend(c_bend(), 0.5 * d, seed);
    EXPECT_NEAR(min_radius(b), truth, 0.02 * truth) << "seed " << seed;
    if (seed == 2) {
      FilletRefineParams off;
      off.min_seen_leg_diameters = 0.0;
      EXPECT_LT(min_radius(b, off), 0.95 * truth);  // without the rule: the smooth tube's overshoot, 81.6
    }
  }
}
