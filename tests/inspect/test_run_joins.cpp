// A bend hidden under a crossing cable: the trace breaks into two runs there, and the bend is measured across the gap
// (run_joins.hpp, pipeline.cpp).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "ewis/inspect/pipeline.hpp"
#include "ewis/inspect/run_joins.hpp"
#include "ewis/raycast/raycaster.hpp"
#include "ewis/scene/primitives.hpp"
#include "ewis/sim/sensor.hpp"
#include "ewis/tubes/trace.hpp"
#include "paths.hpp"
#include "plan_rules.hpp"

using namespace ewis;

namespace {

struct Crossing {
  Scene scene;
  InspectionPlan plan;
  Cloud scan;
  Pose camera_to_cad;
  Eigen::Vector3d corner = Eigen::Vector3d::Zero();  // the middle of A's arc
};

// A (d 5.5) runs straight, bends by 45 deg at R 27.5 (5 d) and runs straight again, 25 mm over a plate; B (d 9.8), a
// straight cable 20 mm higher, crosses over the middle of A's arc. Sensor about 600 mm above.
Crossing make_crossing(std::uint64_t seed) {
  Crossing c;
  test::Turtle t;
  t.pos = {-160, -30, 25};
  t.points = {t.pos};
  t.step = 0.5;
  t.straight(150);
  const Eigen::Vector3d side = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d centre = t.pos + 27.5 * side;
  t.arc(27.5, 45.0, side);
  const Eigen::Vector3d mid_dir = Eigen::AngleAxisd(22.5 * M_PI / 180.0, Eigen::Vector3d::UnitZ()) * (-side);
  c.corner = centre + 27.5 * mid_dir;
  t.straight(140);
  const Mesh ma = make_tube(t.points, 2.75, 32);
  add_element(c.scene, "cable_A", ma.vertices, ma.triangles);
  // B across A's arc at its middle, along the arc's radius there (square to A), 20 mm above it.
  const Eigen::Vector3d over = c.corner + Eigen::Vector3d(0, 0, 20.0);
  const Eigen::Vector3d along = mid_dir;
  const Mesh mb = make_tube({over - 120.0 * along, over + 120.0 * along}, 4.9, 32);
  add_element(c.scene, "cable_B", mb.vertices, mb.triangles);
  const Mesh plate = make_box({-250, -200, -5}, {250, 200, 0});
  add_element(c.scene, "plate", plate.vertices, plate.triangles);
  c.plan.elements = {test::cable_rule("cable_A", 5.5, 15.0, 2.0), test::cable_rule("cable_B", 9.8, 15.0, 2.0)};
  c.camera_to_cad = look_at({20, 10, 620}, {0, 0, 25}, Eigen::Vector3d::UnitY());
  const Raycaster caster(c.scene);
  sim::SensorParams sp;
  sp.seed = seed;
  c.scan = sim::scan(caster, Camera{}, c.camera_to_cad, sp).cloud;
  return c;
}

}  // namespace

// Measured across the gap: the bend's radius and place.
TEST(RunJoins, ABendUnderACrossingCableIsMeasuredAcrossTheGap) {
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const Crossing c = make_crossing(seed);
    InspectParams p;
    p.register_scan = false;  // the true pose
    const InspectionResult r = inspect(c.scene, c.plan, c.scan, c.camera_to_cad, p);
    ASSERT_EQ(r.cables.size(), 2u);
    const CableInspection& a = r.cables[0];
    ASSERT_TRUE(a.found) << "seed " << seed;
    // The crossing cable hides the arc's middle: the trace breaks there.
    ASSERT_GE(a.runs.size(), 2u) << "seed " << seed;
    ASSERT_TRUE(a.min_bend_radius_mm) << "seed " << seed;
    EXPECT_NEAR(*a.min_bend_radius_mm, 27.5, 0.05 * 27.5) << "seed " << seed;
    ASSERT_TRUE(a.min_bend_location) << "seed " << seed;
    EXPECT_LT((*a.min_bend_location - c.corner).norm(), 5.5) << "seed " << seed;
  }
}

// The same scans without the join (each run holds a part of the arc and no leg beyond it: the bend is lost) and with
// the crossing cable's mixed pixels at the gap's ends left in (they pull the fit on both sides tight): the test above
// can fail.
TEST(RunJoins, WithoutTheJoinOrWithTheOccludersMixedPixelsTheBendReadsWrong) {
  int lost_without_join = 0, tight_with_edge_points = 0;
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const Crossing c = make_crossing(seed);
    InspectParams no_join;
    no_join.register_scan = false;
    no_join.joins.enabled = false;
    const CableInspection a1 = inspect(c.scene, c.plan, c.scan, c.camera_to_cad, no_join).cables[0];
    if (!a1.min_bend_radius_mm || std::abs(*a1.min_bend_radius_mm / 27.5 - 1.0) > 0.05) ++lost_without_join;
    InspectParams edge_points;
    edge_points.register_scan = false;
    edge_points.joins.drop_edge_points = false;
    const CableInspection a2 = inspect(c.scene, c.plan, c.scan, c.camera_to_cad, edge_points).cables[0];
    if (a2.min_bend_radius_mm && *a2.min_bend_radius_mm < 0.95 * 27.5) ++tight_with_edge_points;
  }
  EXPECT_GE(lost_without_join, 2);
  EXPECT_GE(tight_with_edge_points, 2);
}

// Two runs of a straight cable across a gap, and a run ended by an attached element: no join.
TEST(RunJoins, NoJoinAcrossAStraightGapOrAnAttachedElement) {
  const auto run = [](Eigen::Vector3d from, Eigen::Vector3d to) {
    TubeTrace t;
    t.found = true;
    t.radius_mm = 2.5;
    const int n = 100;
    for (int i = 0; i <= n; ++i) t.centerline.push_back(from + (to - from) * (double(i) / n));
    return t;
  };
  const std::vector<Eigen::Vector3f> cloud;
  // straight on across a 12 mm gap
  std::vector<TubeTrace> straight = {run({0, 0, 0}, {100, 0, 0}), run({112, 0, 0}, {200, 0, 0})};
  EXPECT_TRUE(join_runs_across_gaps(straight, cloud, 5.0).empty());
  // a 40 deg corner hidden in the gap: joined, the gap between the two near ends
  const Eigen::Vector3d turn = Eigen::AngleAxisd(40 * M_PI / 180, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d::UnitX();
  std::vector<TubeTrace> corner = {run({0, 0, 0}, {100, 0, 0}), run(Eigen::Vector3d(106, 0, 0) + 6 * turn,
                                                                     Eigen::Vector3d(106, 0, 0) + 100 * turn)};
  const std::vector<RunJoin> joins = join_runs_across_gaps(corner, cloud, 5.0);
  ASSERT_EQ(joins.size(), 1u);
  EXPECT_LT((joins[0].gap_start - Eigen::Vector3d(100, 0, 0)).norm(), 1e-9);
  EXPECT_LT((joins[0].gap_end - (Eigen::Vector3d(106, 0, 0) + 6 * turn)).norm(), 1e-9);
  // the joined centreline: 20 d of each run beside the gap, and the gap
  EXPECT_NEAR(polyline_length(joins[0].centerline), 100.0 + (joins[0].gap_end - joins[0].gap_start).norm() + 94.0,
              1.0);
  // the same corner, the first run ended by a clamp there
  corner[0].end_reason_back = "stop region";
  EXPECT_TRUE(join_runs_across_gaps(corner, cloud, 5.0).empty());
  // a jog (an S hidden in the gap): the ends point at each other but their lines cross behind the first end
  const Eigen::Vector3d tilt = Eigen::AngleAxisd(10 * M_PI / 180, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d::UnitX();
  std::vector<TubeTrace> jog = {run({0, 0, 0}, {100, 0, 0}),
                                run(Eigen::Vector3d(112, 9, 0), Eigen::Vector3d(112, 9, 0) + 100 * tilt)};
  EXPECT_TRUE(join_runs_across_gaps(jog, cloud, 5.0).empty());
  // runs that end far apart
  std::vector<TubeTrace> far = {run({0, 0, 0}, {100, 0, 0}), run(Eigen::Vector3d(150, 0, 0) + 6 * turn,
                                                                  Eigen::Vector3d(150, 0, 0) + 100 * turn)};
  EXPECT_TRUE(join_runs_across_gaps(far, cloud, 5.0).empty());
}

// A harness forking (DESIGN "branching harnesses"), its branch of the trunk's diameter traced as a run of its own. When
// the trunk's trace broke at the fork, three run ends meet there: the turn from trunk into branch is no bend hidden
// in a gap (a 20 deg branch read as a 12.3 mm bend so), so none of them is joined, and the fork is reported. When the
// trunk was traced through, the branch's run ends inside the trunk's tube: a fork too. Two runs meeting at a hidden
// corner are joined as before, and no fork.
TEST(RunJoins, AForkIsNoBendAndIsReported) {
  const auto run = [](Eigen::Vector3d from, Eigen::Vector3d to) {
    TubeTrace t;
    t.found = true;
    t.radius_mm = 3.6;
    const int n = 100;
    for (int i = 0; i <= n; ++i) t.centerline.push_back(from + (to - from) * (double(i) / n));
    return t;
  };
  const std::vector<Eigen::Vector3f> cloud;
  const double d = 7.2;
  const Eigen::Vector3d turn = Eigen::AngleAxisd(20 * M_PI / 180, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d::UnitX();
  const Eigen::Vector3d fork(100, 0, 0);
  // the trunk before the fork and the branch leaving it: a corner hidden in the gap, joined
  std::vector<TubeTrace> runs = {run({0, 0, 0}, fork), run(fork + 4 * turn, fork + 80 * turn)};
  EXPECT_EQ(join_runs_across_gaps(runs, cloud, d).size(), 1u);
  EXPECT_TRUE(run_forks(runs, d).empty());
  // ... and the trunk going on beyond the fork: three ends meet
  runs.push_back(run({103, 0, 0}, {200, 0, 0}));
  EXPECT_TRUE(join_runs_across_gaps(runs, cloud, d).empty());
  std::vector<Eigen::Vector3d> forks = run_forks(runs, d);
  ASSERT_EQ(forks.size(), 1u);
  EXPECT_LT((forks[0] - fork).norm(), 3.0);
  // the trunk traced through the fork, the branch's run ending inside its tube
  const std::vector<TubeTrace> through = {run({0, 0, 0}, {200, 0, 0}), run(fork + 1.5 * turn, fork + 80 * turn)};
  forks = run_forks(through, d);
  ASSERT_EQ(forks.size(), 1u);
  EXPECT_LT((forks[0] - fork).norm(), 2.0);
  // a run ending where another ends (a clamp's two sides, each side's end not stopped there): no fork
  const std::vector<TubeTrace> in_line = {run({0, 0, 0}, {100, 0, 0}), run({104, 0, 0}, {200, 0, 0})};
  EXPECT_TRUE(run_forks(in_line, d).empty());
}
