// Runs of two cables on the same scan points (run_conflicts.hpp).
#include <gtest/gtest.h>

#include <numeric>

#include "ewis/inspect/run_conflicts.hpp"
#include "ewis/scene/primitives.hpp"

using namespace ewis;

namespace {

// A run along the straight axis a -> b (10 segments) made of the scan points [first, first + count).
TubeTrace run(const Eigen::Vector3d& a, const Eigen::Vector3d& b, std::uint32_t first, std::uint32_t count,
              double radius_mm = 4.8) {
  TubeTrace t;
  t.found = true;
  for (int i = 0; i < 10; ++i) {
    SubCable s;
    s.cylinder.start = a + (b - a) * (i / 10.0);
    s.cylinder.end = a + (b - a) * ((i + 1) / 10.0);
    s.cylinder.radius_mm = radius_mm;
    t.segments.push_back(s);
  }
  t.radius_mm = radius_mm;
  t.points.resize(count);
  std::iota(t.points.begin(), t.points.end(), first);
  return t;
}

// Two parallel cables (r 4.8) 17 mm apart: A's CAD along y = 0 (its as-built course 4 mm toward C, as where a
// defect moved it), C's along y = 17.
Scene two_cables() {
  Scene s;
  const Mesh a = make_cylinder({-200, 0, 0}, {200, 0, 0}, 4.8);
  const Mesh c = make_cylinder({-200, 17, 0}, {200, 17, 0}, 4.8);
  add_element(s, "cable_A", a.vertices, a.triangles);
  add_element(s, "cable_C", c.vertices, c.triangles);
  return s;
}

// The scan points: [0, 1000) on A's top at y = 4 (its as-built course), the rest on C's top at y = 17, spread along x.
std::vector<Eigen::Vector3f> scan_points() {
  std::vector<Eigen::Vector3f> p(3000);
  for (std::size_t i = 0; i < p.size(); ++i)
    p[i] = Eigen::Vector3f(-190.0f + 380.0f * float(i % 1000) / 1000.0f, i < 1000 ? 4.0f : 17.0f, 4.8f);
  return p;
}

std::vector<CableInspection> cables_with(std::vector<TubeTrace> a_runs, std::vector<TubeTrace> c_runs) {
  std::vector<CableInspection> v(2);
  v[0].name = "cable_A";
  v[0].element = 0;
  v[0].runs = std::move(a_runs);
  v[1].name = "cable_C";
  v[1].element = 1;
  v[1].runs = std::move(c_runs);
  return v;
}

}  // namespace

// A's second run started on C (campaign scene_027 at 1.5x noise): it shares C's points and lies on C's CAD, so
// it is dropped; C keeps its run, whichever of C's runs it is.
TEST(RunConflicts, ARunOnTheNeighbourIsDropped) {
  const Scene scene = two_cables();
  for (bool c_first_run : {true, false}) {
    std::vector<TubeTrace> c_runs;
    if (!c_first_run) c_runs.push_back(run({100, 17, 0}, {190, 17, 0}, 2000, 500));
    c_runs.push_back(run({-160, 17, 0}, {0, 17, 0}, 1000, 800));
    auto cables = cables_with({run({0, 4, 0}, {190, 4, 0}, 0, 900),          // A itself
                               run({0, 17.3, 0}, {-160, 17.2, 0}, 1050, 700)},  // on C, C's points
                              c_runs);
    EXPECT_EQ(drop_runs_on_other_cables(cables, scene, scan_points()), 1u);
    ASSERT_EQ(cables[0].runs.size(), 1u);
    EXPECT_EQ(cables[0].runs[0].points.front(), 0u);
    EXPECT_EQ(cables[1].runs.size(), c_runs.size());
  }
}

// Runs that share a few points (two cables touching side by side: a handful of boundary points claimed by both)
// are both kept.
TEST(RunConflicts, TouchingCablesKeepTheirRuns) {
  const Scene scene = two_cables();
  auto cables = cables_with({run({-190, 4, 0}, {190, 4, 0}, 0, 1000)}, {run({-190, 17, 0}, {190, 17, 0}, 900, 1000)});
  EXPECT_EQ(drop_runs_on_other_cables(cables, scene, scan_points()), 0u);
  EXPECT_EQ(cables[0].runs.size(), 1u);
  EXPECT_EQ(cables[1].runs.size(), 1u);
}

namespace {

// A stretch of cable_A's course (points [400, 800) along y = 4) traced by cable_A (plan diameter a_diameter_mm; its
// runs `a_runs`, the stretch among them) and by cable_C (plan diameter c_diameter_mm; its own run on C's points [1000,
// 1400) read at c_own_radius_mm, then the stretch read at c_stretch_radius_mm): the stretch is A's, so C's run on it
// is dropped and A keeps every run.
void expect_the_stretch_kept_by_a(std::vector<TubeTrace> a_runs, double a_diameter_mm, double c_own_radius_mm,
                                  double c_stretch_radius_mm, double c_diameter_mm) {
  const std::size_t a_count = a_runs.size();
  auto cables = cables_with(std::move(a_runs), {run({-190, 17, 0}, {190, 17, 0}, 1000, 400, c_own_radius_mm),
                                                run({-160, 4, 0}, {0, 4, 0}, 400, 400, c_stretch_radius_mm)});
  cables[0].nominal_diameter_mm = a_diameter_mm;
  cables[1].nominal_diameter_mm = c_diameter_mm;
  EXPECT_EQ(drop_runs_on_other_cables(cables, two_cables(), scan_points()), 1u);
  EXPECT_EQ(cables[0].runs.size(), a_count);
  ASSERT_EQ(cables[1].runs.size(), 1u);
  EXPECT_EQ(cables[1].runs[0].points.front(), 1000u);
}

}  // namespace

// Two gauges (plan 4.6 and 4.0 mm) whose runs read low alike (2.13 and 1.85 mm: the fit's bias on thin cables), and a
// stretch of the thicker one traced by both (2.09 and 2.11 mm): nearer the thinner one's plan radius (2.0) than the
// thicker one's (2.3), but the thicker one's gauge as measured: the place is the thicker cable's (K40 scene_032: it
// went to the thinner one, whose trace then took the other's place, a false contact).
TEST(RunConflicts, TheSharedStretchGoesToTheGaugeItMeasuresAsTheRunsRead) {
  expect_the_stretch_kept_by_a({run({0, 4, 0}, {190, 4, 0}, 0, 400, 2.13), run({-160, 4, 0}, {0, 4, 0}, 400, 400, 2.09)},
                               4.6, 1.85, 2.11, 4.0);
}

// A cable the sensor hardly sees (a side view) has its other runs on its neighbours, so their radius is not its
// gauge: without a gauge of its own for each cable the plan radii decide (V20 scene_014_v3: a 4.9 mm cable's stretch,
// read 2.43 mm, went to a 4.4 mm cable whose other run lay on a 6.2 mm one).
TEST(RunConflicts, AGaugeReadOnAnotherCableDoesNotDecide) {
  expect_the_stretch_kept_by_a({run({-160, 4, 0}, {0, 4, 0}, 400, 400, 2.42)}, 4.9, 3.1, 2.44, 4.4);
}
