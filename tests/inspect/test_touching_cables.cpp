// Two cables tied side by side (a bundle), touching or nearly, scanned by the virtual sensor: each is traced on
// its own points, not the neighbour's sliver beside the contact (pipeline.cpp, "Touching cables").
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "ewis/inspect/pipeline.hpp"
#include "ewis/raycast/raycaster.hpp"
#include "ewis/scene/primitives.hpp"
#include "ewis/sim/sensor.hpp"
#include "ewis/tubes/trace.hpp"
#include "paths.hpp"
#include "plan_rules.hpp"

using namespace ewis;

namespace {

struct Bundle {
  Scene scene;
  InspectionPlan plan;
  Cloud scan;
  Pose camera_to_cad;
  double length_a_mm = 0, length_b_mm = 0;
};

// A (d 5.6) runs straight, bends by 60 deg at R 120 and runs straight again, 25 mm over a plate; B (d 4) runs
// beside it at `gap_mm` (the arc concentric), towards the bend's outside. Sensor 600 mm above.
Bundle make_bundle(double gap_mm, std::uint64_t seed) {
  Bundle b;
  const double ra = 2.8, rb = 2.0;
  test::Turtle t;
  t.pos = {-180, -40, 25};
  t.points = {t.pos};
  t.step = 0.5;
  t.straight(140);
  t.arc(120.0, 60.0, Eigen::Vector3d::UnitY());
  t.straight(120);
  const std::vector<Eigen::Vector3d>& a = t.points;
  std::vector<Eigen::Vector3d> other;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Eigen::Vector3d tan = (a[std::min(i + 1, a.size() - 1)] - a[i == 0 ? 0 : i - 1]).normalized();
    // to the bend's outside: the arc turns towards +y, so -y of the tangent's left
    other.push_back(a[i] - (ra + rb + gap_mm) * Eigen::Vector3d::UnitZ().cross(tan).normalized());
  }
  b.length_a_mm = polyline_length(a);
  b.length_b_mm = polyline_length(other);
  const Mesh ma = make_tube(a, ra, 32), mb = make_tube(other, rb, 32);
  add_element(b.scene, "cable_A", ma.vertices, ma.triangles);
  add_element(b.scene, "cable_B", mb.vertices, mb.triangles);
  const Mesh plate = make_box({-250, -200, -5}, {250, 200, 0});
  add_element(b.scene, "plate", plate.vertices, plate.triangles);
  b.plan.elements = {test::cable_rule("cable_A", 2 * ra, 40.0, 3.0), test::cable_rule("cable_B", 2 * rb, 40.0, 3.0)};
  b.camera_to_cad = look_at({30, 10, 620}, {0, 0, 25}, Eigen::Vector3d::UnitY());
  const Raycaster caster(b.scene);
  sim::SensorParams sp;
  sp.seed = seed;
  b.scan = sim::scan(caster, Camera{}, b.camera_to_cad, sp).cloud;
  return b;
}

}  // namespace

TEST(TouchingCables, EachIsTracedOnItsOwnSurface) {
  for (const double gap : {0.0, 0.4}) {
    const Bundle b = make_bundle(gap, 3);
    InspectParams p;
    p.register_scan = false;  // the true pose
    const InspectionResult r = inspect(b.scene, b.plan, b.scan, b.camera_to_cad, p);
    ASSERT_EQ(r.cables.size(), 2u);
    const CableInspection &a = r.cables[0], &c = r.cables[1];
    ASSERT_TRUE(a.found && c.found) << "gap " << gap;
    EXPECT_NEAR(a.diameter_mm, 5.6, 0.05 * 5.6) << "gap " << gap;
    ASSERT_TRUE(a.min_bend_radius_mm && c.min_bend_radius_mm);
    EXPECT_NEAR(*a.min_bend_radius_mm, 120.0, 0.05 * 120.0) << "gap " << gap;
    EXPECT_NEAR(*c.min_bend_radius_mm, 124.8 + gap, 0.05 * 124.8) << "gap " << gap;
    EXPECT_NEAR(c.diameter_mm, 4.0, 0.05 * 4.0) << "gap " << gap;
    EXPECT_GE(a.length_mm, 0.9 * b.length_a_mm) << "gap " << gap;
    EXPECT_GE(c.length_mm, 0.9 * b.length_b_mm) << "gap " << gap;
    EXPECT_LE(c.length_mm, 1.03 * b.length_b_mm) << "gap " << gap;
    // the clearance defect between them, at its gap
    bool seen = false;
    for (const CableInspection* ci : {&a, &c})
      for (const Interference& f : ci->interferences)
        if (f.with && (*f.with == "cable_A" || *f.with == "cable_B")) {
          seen = true;
          EXPECT_NEAR(f.min_distance_mm, gap, 0.4) << "gap " << gap;
        }
    EXPECT_TRUE(seen) << "gap " << gap;
    // nothing else: no foreign object made of a neighbour's sliver
    for (const CableInspection* ci : {&a, &c})
      for (const Interference& f : ci->interferences) EXPECT_TRUE(f.with.has_value()) << "gap " << gap;
  }
}

// Without the second trace the touching pair is measured wrong: the test above can fail.
TEST(TouchingCables, TracedAloneTheyTakeInTheNeighbour) {
  const Bundle b = make_bundle(0.0, 3);
  InspectParams p;
  p.register_scan = false;
  p.untangle_touching = false;
  const InspectionResult r = inspect(b.scene, b.plan, b.scan, b.camera_to_cad, p);
  ASSERT_EQ(r.cables.size(), 2u);
  const CableInspection& a = r.cables[0];
  const bool wrong = !a.found || std::abs(a.diameter_mm / 5.6 - 1.0) > 0.1 || !a.min_bend_radius_mm ||
                     std::abs(*a.min_bend_radius_mm / 120.0 - 1.0) > 0.1;
  EXPECT_TRUE(wrong) << "d " << a.diameter_mm;
}

namespace {

// C (d 10) runs straight over a plate; A (d 9) runs beside it, 15 mm off axis to axis, but A's CAD lies 1 mm from C's
// axis (the as-built cable moved off its CAD, onto its neighbour's place). Connectors hide the tubes' open ends.
struct Displaced {
  Scene cad;
  InspectionPlan plan;
  Cloud scan;
  Pose camera_to_cad;
};

std::vector<Eigen::Vector3d> line_at(double y) {
  test::Turtle t;
  t.pos = {-150, y, 25};
  t.points = {t.pos};
  t.step = 0.5;
  t.straight(300);
  return t.points;
}

Displaced make_displaced(std::uint64_t seed) {
  Displaced d;
  const Mesh plate = make_box({-250, -200, -5}, {250, 200, 0});
  const Mesh j1 = make_box({-160, -12, 0}, {-130, 27, 40}), j2 = make_box({130, -12, 0}, {160, 27, 40});
  const Mesh c = make_tube(line_at(0.0), 5.0, 32), a = make_tube(line_at(15.0), 4.5, 32),
             a_cad = make_tube(line_at(1.0), 4.5, 32);
  Scene built;
  for (Scene* s : {&built, &d.cad}) {
    add_element(*s, "cable_C", c.vertices, c.triangles);
    add_element(*s, "plate", plate.vertices, plate.triangles);
    add_element(*s, "connector_J1", j1.vertices, j1.triangles);
    add_element(*s, "connector_J2", j2.vertices, j2.triangles);
  }
  add_element(built, "cable_A", a.vertices, a.triangles);
  add_element(d.cad, "cable_A", a_cad.vertices, a_cad.triangles);
  d.plan.elements = {test::cable_rule("cable_C", 10.0, 40.0, 2.0), test::cable_rule("cable_A", 9.0, 40.0, 2.0)};
  d.camera_to_cad = look_at({30, 40, 620}, {0, 0, 25}, Eigen::Vector3d::UnitY());
  const Raycaster caster(built);
  sim::SensorParams sp;
  sp.seed = seed;
  d.scan = sim::scan(caster, Camera{}, d.camera_to_cad, sp).cloud;
  return d;
}

// The length of a cable's runs lying within `tol` of the line y = `y`, z = 25.
double length_along(const CableInspection& ci, double y, double tol) {
  double len = 0.0;
  for (const TubeTrace& t : ci.runs)
    for (std::size_t i = 1; i < t.centerline.size(); ++i) {
      const Eigen::Vector3d m = 0.5 * (t.centerline[i] + t.centerline[i - 1]);
      if (std::hypot(m.y() - y, m.z() - 25.0) <= tol) len += (t.centerline[i] - t.centerline[i - 1]).norm();
    }
  return len;
}

}  // namespace

// A's first trace takes C (its CAD samples lie on C); C's CAD claims the place, so A is traced again without C's
// points and found on its own, 15 mm away; C keeps all of its points.
TEST(TouchingCables, ACableMovedOntoItsNeighboursPlaceIsTracedOnItsOwnPoints) {
  for (const std::uint64_t seed : {1u, 2u}) {
    const Displaced d = make_displaced(seed);
    InspectParams p;
    p.register_scan = false;  // the true pose
    const InspectionResult r = inspect(d.cad, d.plan, d.scan, d.camera_to_cad, p);
    ASSERT_EQ(r.cables.size(), 2u);
    const CableInspection &c = r.cables[0], &a = r.cables[1];
    ASSERT_TRUE(c.found && a.found) << "seed " << seed;
    EXPECT_GT(length_along(a, 15.0, 2.0), 220.0) << "seed " << seed;
    EXPECT_LT(length_along(a, 0.0, 4.0), 10.0) << "seed " << seed;
    EXPECT_GT(length_along(c, 0.0, 2.0), 220.0) << "seed " << seed;
    EXPECT_NEAR(c.diameter_mm, 10.0, 0.05 * 10.0) << "seed " << seed;
    EXPECT_NEAR(a.diameter_mm, 9.0, 0.05 * 9.0) << "seed " << seed;
  }
}

// The control: untangled by the nearer surfaces alone (no retrace without the neighbour's run), the two split C
// between them and A is not traced on its own points in at least one of the two scans. (Left out of the sanitized
// pass with the other controls, scripts/test.sh.)
TEST(TouchingCables, WithoutTheRetraceTheMovedCableTakesItsNeighbour) {
  int wrong_without = 0;
  for (const std::uint64_t seed : {1u, 2u}) {
    const Displaced d = make_displaced(seed);
    InspectParams without;
    without.register_scan = false;
    without.retrace_runs_on_others = false;
    const InspectionResult r0 = inspect(d.cad, d.plan, d.scan, d.camera_to_cad, without);
    ASSERT_EQ(r0.cables.size(), 2u);
    if (!r0.cables[1].found || length_along(r0.cables[1], 15.0, 2.0) < 220.0 ||
        length_along(r0.cables[0], 0.0, 2.0) < 220.0)
      ++wrong_without;
  }
  EXPECT_GE(wrong_without, 1);
}
