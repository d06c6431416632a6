// trace_tube on simulated scans with known truth (DESIGN.md hard cases; issue 5 accuracy goals).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <cstdlib>

#include "ewis/filter/resolution.hpp"
#include "ewis/search/kdtree.hpp"
#include "ewis/tubes/trace.hpp"
#include "tubes/synthetic_scan.hpp"

namespace {

using Eigen::Vector3d;

struct Metrics {
  double rms = 0, max = 0;  // centreline distance to the truth
  double coverage = 0;      // of the true centreline, within 1 mm of the chain
  double diameter_err_pct = 0;
};

Metrics measure(const ewis::TubeTrace& t, const std::vector<Vector3d>& truth, double r_true) {
  Metrics m;
  double ss = 0;
  int n = 0;
  for (const Vector3d& p : t.centerline) {
    const double d = synth::distance_to_polyline(truth, p);
    ss += d * d;
    m.max = std::max(m.max, d);
    ++n;
  }
  m.rms = n ? std::sqrt(ss / n) : 1e9;
  m.coverage = ewis::chain_coverage(t, truth, 1.0);
  m.diameter_err_pct = 100.0 * (t.radius_mm / r_true - 1.0);
  return m;
}

void print(const char* name, const ewis::TubeTrace& t, const Metrics& m, const std::vector<Vector3d>* truth = nullptr) {
  if (truth && std::getenv("TUBES_DEBUG"))
    for (const auto& sg : t.segments) {
      double a0 = 0, a1 = 0;
      const double e0 = synth::distance_to_polyline(*truth, sg.cylinder.start, &a0);
      const double e1 = synth::distance_to_polyline(*truth, sg.cylinder.end, &a1);
      std::printf("  seg %.1f->%.1f err %.3f %.3f r %.3f pts %u rms %.3f br %d\n", a0, a1, e0, e1, sg.cylinder.radius_mm,
                  sg.points, sg.rms_mm, sg.bridged);
    }
  std::printf("[%s] found %d r %.3f rms %.3f max %.3f cov %.3f derr %.2f%% len %.1f segs %zu gaps %zu pts %zu ends %s/%s\n",
              name, t.found, t.radius_mm, m.rms, m.max, m.coverage, m.diameter_err_pct, t.length_mm,
              t.segments.size(), t.gaps.size(), t.points.size(), t.end_reason_front.c_str(), t.end_reason_back.c_str());
}

// A straight oblique tube of radius r, 150 mm long, its middle 600 mm from the sensor (at the origin).
const Vector3d kObliqueDir = Vector3d(1, 0.3, 0.2).normalized();
const Vector3d kObliqueMid(5, -10, 600);
std::vector<Vector3d> oblique_axis() { return synth::line(kObliqueMid - kObliqueDir * 75, kObliqueMid + kObliqueDir * 75); }
synth::Scan oblique_tube_scan(double r) {
  synth::Scene scene;
  scene.add_tube(oblique_axis(), r, 0);
  return synth::render(scene);
}

// That tube traced from a seed on its seen side: the goals for diameter, centreline and coverage.
void check_straight_tube(double r, const ewis::TubeParams& params, const char* name) {
  const Vector3d mid = kObliqueMid;
  const auto truth = oblique_axis();
  const synth::Scan scan = oblique_tube_scan(r);
  const ewis::KdTree tree(scan.cloud.points);
  const ewis::TubeTrace t = ewis::trace_tube(scan.cloud, tree, mid - mid.normalized() * r, params);
  const Metrics m = measure(t, truth, r);
  print(name, t, m);
  ASSERT_TRUE(t.found);
  EXPECT_LE(std::abs(m.diameter_err_pct), 3.0);
  EXPECT_LE(m.rms, 0.3);
  EXPECT_GE(m.coverage, 0.95);
}

class StraightTube : public ::testing::TestWithParam<double> {};

TEST_P(StraightTube, DiameterAndCentrelineWithinGoals) { check_straight_tube(GetParam() / 2, {}, "straight"); }

INSTANTIATE_TEST_SUITE_P(Diameters, StraightTube, ::testing::Values(5.0, 10.0, 30.0));

// The same with the sensor known (at the origin, as in a scan's own frame): the fit's sensor must be taken in
// the frame of the step's points (it was not: nothing was found).
TEST(TraceTube, StraightTubeWithTheSensorAtTheOrigin) {
  ewis::TubeParams params;
  params.has_sensor = true;
  params.sensor_position = Vector3d::Zero();
  check_straight_tube(5.0, params, "straight, sensor known");
}

// Seed on the visible surface of the tube at centreline point c.
Vector3d surface_seed(const Vector3d& c, double r) { return c - c.normalized() * r; }

// Fraction of the trace's points that are closer to `other`'s surface than to `own`'s (wrong object).
double wrong_fraction(const ewis::TubeTrace& t, const synth::Scan& scan, int own) {
  int wrong = 0, total = 0;
  for (std::uint32_t i : t.points) {
    ++total;
    wrong += scan.label[i] >= 0 && scan.label[i] != own;
  }
  return total ? static_cast<double>(wrong) / total : 0.0;
}

// Straight leg, torus arc of bend radius R turning `arc_deg`, straight leg (legs `leg_mm` long), in the plane
// turned by `rot`, placed at `o`: a dense centreline.
std::vector<Vector3d> leg_arc_leg(double R, double arc_deg, double leg_mm, const Eigen::Matrix3d& rot, const Vector3d& o,
                                  int arc_samples) {
  const double arc = arc_deg * M_PI / 180.0;
  std::vector<Vector3d> truth;
  for (const Vector3d& p : synth::line(Vector3d(-leg_mm, -R, 0), Vector3d(0, -R, 0))) truth.push_back(o + rot * p);
  for (const Vector3d& p :
       synth::curve([&](double a) { return Vector3d(R * std::sin(a), -R * std::cos(a), 0); }, 0, arc, arc_samples))
    truth.push_back(o + rot * p);
  const Vector3d e(R * std::sin(arc), -R * std::cos(arc), 0), te(std::cos(arc), std::sin(arc), 0);
  for (const Vector3d& p : synth::line(e, e + te * leg_mm)) truth.push_back(o + rot * p);
  return truth;
}

TEST(TraceTube, BentTubeTracedEndToEnd) {
  // a 10 mm tube: straight leg, 150 deg torus arc of bend radius 50 mm, straight leg; bend plane tilted
  const double r = 5.0, R = 50.0;
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(0.5, Vector3d(1, 0.2, 0).normalized()).toRotationMatrix();
  const std::vector<Vector3d> truth = leg_arc_leg(R, 150.0, 40.0, rot, Vector3d(0, 0, 600), 400);
  synth::Scene scene;
  scene.add_tube(truth, r, 0);
  const synth::Scan scan = synth::render(scene);
  const ewis::KdTree tree(scan.cloud.points);
  const ewis::TubeTrace t = ewis::trace_tube(scan.cloud, tree, surface_seed(truth[30], r), {});
  const Metrics m = measure(t, truth, r);
  print("bent", t, m);
  ASSERT_TRUE(t.found);
  EXPECT_GE(m.coverage, 0.95);
  EXPECT_LE(m.rms, 0.3);
  EXPECT_LE(std::abs(m.diameter_err_pct), 3.0);
  EXPECT_NEAR(t.length_mm, synth::distance_to_polyline(truth, truth.back()) + ewis::polyline_length(truth), 4.0);
}

// A closed ring (a cable looped round, 60 mm radius, 8 mm thick, its plane tilted 30 deg from facing the sensor):
// the trace goes round once. The two walks from the start run at once; the forward one stops on reaching its own
// beginning, the backward one is cut where it meets the forward one (it went round too): what is left must be one
// turn, with no stretch twice.
TEST(TraceTube, AClosedRingIsTracedOnceRound) {
  const double r = 4.0, R = 60.0;
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(M_PI / 6, Vector3d(1, 0.3, 0).normalized()).toRotationMatrix();
  const Vector3d o(0, 0, 600);
  const std::vector<Vector3d> truth = synth::curve(
      [&](double a) { return Vector3d(o + rot * Vector3d(R * std::cos(a), R * std::sin(a), 0)); }, 0, 2 * M_PI, 720);
  synth::Scene scene;
  scene.add_tube(truth, r, 0);
  const synth::Scan scan = synth::render(scene);
  const ewis::KdTree tree(scan.cloud.points);
  const ewis::TubeTrace t = ewis::trace_tube(scan.cloud, tree, surface_seed(truth[100], r), {});
  const Metrics m = measure(t, truth, r);
  print("ring", t, m);
  ASSERT_TRUE(t.found);
  EXPECT_GE(m.coverage, 0.95);
  EXPECT_LE(m.rms, 0.3);
  EXPECT_TRUE(t.end_reason_front == "loop" || t.end_reason_back == "loop")
      << t.end_reason_front << " / " << t.end_reason_back;
  // once round: at most the circumference and one step's reach beyond it
  EXPECT_LE(t.length_mm, 2 * M_PI * R + 2 * r);
  EXPECT_GE(t.length_mm, 0.95 * 2 * M_PI * R);
}

// A 3 mm cable in a sparse scan (0.75 mm pixels at 600 mm, 0.2 mm noise along the rays, 40 % outliers): four
// points across its seen side, 10-20 per step window. The starting arc (counted in 10 deg sectors of 2 points)
// read 40-90 deg and the radius of 20-point fits wandered by 50 %: nothing or a few tens of mm was traced.
TEST(TraceTube, ThinTubeInASparseNoisyScan) {
  const double r = 1.5, R = 40.0;
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(0.4, Vector3d(0.3, 1, 0).normalized()).toRotationMatrix();
  const std::vector<Vector3d> truth = leg_arc_leg(R, 60.0, 80.0, rot, Vector3d(0, 0, 600), 200);
  synth::Scene scene;
  scene.add_tube(truth, r, 0);
  ewis::TubeParams params;
  params.radius_mm = r;
  params.has_sensor = true;
  params.sensor_position = Vector3d::Zero();
  for (std::uint64_t seed : {3, 5, 8}) {
    const synth::Scan scan = synth::render(scene, 0.2, 0.4, seed, 0.75);
    const ewis::KdTree tree(scan.cloud.points);
    const ewis::TubeTrace t = ewis::trace_tube(scan.cloud, tree, surface_seed(truth[100], r), params);
    const Metrics m = measure(t, truth, r);
    print("thin, sparse", t, m);
    ASSERT_TRUE(t.found) << "seed " << seed;
    EXPECT_GE(m.coverage, 0.9) << "seed " << seed;
    EXPECT_LE(m.rms, 0.4) << "seed " << seed;
    EXPECT_LE(std::abs(m.diameter_err_pct), 15.0) << "seed " << seed;
  }
}

// A single wire, 1.7 mm across, bent at 15 mm over a plate 30 mm behind it (0.5 mm pixels at 600 mm, 0.2 mm noise
// along the rays, 40 % outliers): 3-4 points across its seen side, whose fits read a free radius anywhere from
// 0.5 to 1.4 mm and whose curvature does not rise above the noise. Held at the hinted radius (thin_max_px), the
// axis alone is fitted and the wire is traced whole, its centreline within 0.06-0.08 mm (rms); with every radius
// fitted it is lost or followed 0.18 mm off.
void check_wire(double pixel_mm, bool fitted_fails) {
  const double r = 0.85, R = 15.0;
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(0.3, Vector3d(1, 0.4, 0).normalized()).toRotationMatrix();
  const std::vector<Vector3d> truth = leg_arc_leg(R, 70.0, 60.0, rot, Vector3d(0, 0, 600), 200);
  synth::Scene scene;
  scene.add_tube(truth, r, 0);
  scene.add_rect(Vector3d(-90, -90, 640), Vector3d(180, 0, 0), Vector3d(0, 180, 0), 1);
  ewis::TubeParams held;
  held.radius_mm = r;
  held.has_sensor = true;
  held.sensor_position = Vector3d::Zero();
  held.thin_max_px = 5.0;
  ewis::TubeParams fitted = held;
  fitted.thin_max_px = 0.0;
  for (std::uint64_t seed : {3, 5, 8}) {
    const synth::Scan scan = synth::render(scene, 0.2, 0.4, seed, pixel_mm);
    const ewis::KdTree tree(scan.cloud.points);
    const ewis::TubeTrace t = ewis::trace_tube(scan.cloud, tree, surface_seed(truth[100], r), held);
    const Metrics m = measure(t, truth, r);
    print("wire, radius held", t, m, &truth);
    ASSERT_TRUE(t.found) << "seed " << seed;
    EXPECT_GE(m.coverage, 0.9) << "seed " << seed;
    EXPECT_LE(m.rms, 0.15) << "seed " << seed;
    EXPECT_LE(wrong_fraction(t, scan, 0), 0.02) << "seed " << seed;
    const ewis::TubeTrace f = ewis::trace_tube(scan.cloud, tree, surface_seed(truth[100], r), fitted);
    const Metrics mf = f.found ? measure(f, truth, r) : Metrics{};
    print("wire, radius fitted", f, mf);
    // fitted, the trace loses the wire (seed 5: 30 % of it) or follows its axis 2.3-3.3 times less exactly
    if (fitted_fails) {
      EXPECT_TRUE(mf.coverage < 0.5 || mf.rms > 1.5 * m.rms) << "seed " << seed;
    }
  }
}

TEST(TraceTube, AWireAFewPointsAcrossIsTracedWithItsRadiusHeld) { check_wire(0.5, true); }

TEST(TraceTube, ParallelTubesTwoMillimetresApartNeverJump) {
  // same diameter, 2 mm apart; tube A shorter, so its ends face B's continuation
  const double r = 5.0;
  const Vector3d dir = Vector3d(1, 0.1, 0.15).normalized();
  const Vector3d side = dir.cross(Vector3d(0, 0, 1)).normalized();
  const Vector3d mid(0, 0, 600);
  const auto a = synth::line(mid - dir * 50, mid + dir * 50);
  const auto b = synth::line(mid + side * (2 * r + 2) - dir * 100, mid + side * (2 * r + 2) + dir * 100);
  synth::Scene scene;
  scene.add_tube(a, r, 0);
  scene.add_tube(b, r, 1);
  const synth::Scan scan = synth::render(scene);
  const ewis::KdTree tree(scan.cloud.points);
  const ewis::TubeTrace t = ewis::trace_tube(scan.cloud, tree, surface_seed(mid, r), {});
  const Metrics m = measure(t, a, r);
  print("parallel", t, m);
  ASSERT_TRUE(t.found);
  EXPECT_LE(m.max, 1.5);  // never on B (B's axis is 12 mm away)
  EXPECT_GE(m.coverage, 0.95);
  EXPECT_LE(std::abs(m.diameter_err_pct), 3.0);
  EXPECT_LE(wrong_fraction(t, scan, 0), 0.005);
  // and B traced from its own seed stays on B
  const Vector3d mb = mid + side * (2 * r + 2) + dir * 70;
  const ewis::TubeTrace tb = ewis::trace_tube(scan.cloud, tree, surface_seed(mb, r), {});
  const Metrics mbm = measure(tb, b, r);
  print("parallel-B", tb, mbm);
  EXPECT_LE(mbm.max, 1.5);
  EXPECT_GE(mbm.coverage, 0.95);
  EXPECT_LE(wrong_fraction(tb, scan, 1), 0.005);
}

TEST(TraceTube, CrossingTubeLowerTracedThroughTheHole) {
  const double r = 5.0;
  const Vector3d o(0, 0, 620);
  const auto lower = synth::line(o + Vector3d(-80, 0, 0), o + Vector3d(80, 0, 0));
  // the upper tube lies on the lower one (touching), nearer the sensor, across it
  const auto upper = synth::line(o + Vector3d(0, -80, -2 * r), o + Vector3d(0, 80, -2 * r));
  synth::Scene scene;
  scene.add_tube(lower, r, 0);
  scene.add_tube(upper, r, 1);
  const synth::Scan scan = synth::render(scene);
  const ewis::KdTree tree(scan.cloud.points);
  const ewis::TubeTrace t = ewis::trace_tube(scan.cloud, tree, surface_seed(o + Vector3d(-50, 0, 0), r), {});
  const Metrics m = measure(t, lower, r);
  print("crossing-lower", t, m);
  ASSERT_TRUE(t.found);
  EXPECT_GE(m.coverage, 0.95);
  EXPECT_LE(m.max, 1.5);
  ASSERT_EQ(t.gaps.size(), 1u);
  EXPECT_LT(std::abs(t.gaps[0].start.x() - o.x()), 12.0);
  EXPECT_LT(std::abs(t.gaps[0].end.x() - o.x()), 12.0);
  EXPECT_LE(wrong_fraction(t, scan, 0), 0.005);
  const ewis::TubeTrace tu = ewis::trace_tube(scan.cloud, tree, surface_seed(o + Vector3d(0, 40, -2 * r), r), {});
  const Metrics mu = measure(tu, upper, r);
  print("crossing-upper", tu, mu);
  EXPECT_GE(mu.coverage, 0.95);
  EXPECT_LE(mu.max, 1.5);
  EXPECT_TRUE(tu.gaps.empty());
}

TEST(TraceTube, TubeLyingOnAPlaneIsNotPulledIn) {
  const double r = 5.0;
  const Vector3d n = Vector3d(0, -0.35, -1).normalized();  // plane normal, towards the sensor
  const Vector3d dir = Vector3d(1, 0, 0).cross(n).cross(n).normalized() * -1.0;
  const Vector3d c(0, 0, 600);
  const auto truth = synth::line(c - dir * 70, c + dir * 70);
  synth::Scene scene;
  scene.add_tube(truth, r, 0);
  const Vector3d side = n.cross(dir).normalized();
  scene.add_rect(c - n * r - dir * 100 - side * 40, dir * 200, side * 80, 1);
  const synth::Scan scan = synth::render(scene);
  const ewis::KdTree tree(scan.cloud.points);
  const ewis::TubeTrace t = ewis::trace_tube(scan.cloud, tree, surface_seed(c, r), {});
  const Metrics m = measure(t, truth, r);
  print("on-plane", t, m, &truth);
  ASSERT_TRUE(t.found);
  EXPECT_LE(std::abs(m.diameter_err_pct), 3.0);
  EXPECT_LE(m.rms, 0.3);
  EXPECT_LE(m.max, 2.5);          // an end may overshoot a little along the plane's strip under the axis
  EXPECT_GE(m.coverage, 0.95);
  EXPECT_LE(t.length_mm, 145.0);  // but it is not continued along the plane
  EXPECT_LE(wrong_fraction(t, scan, 0), 0.02);
}

TEST(TraceTube, HelixNonPlanarBend) {
  const double r = 4.0, R = 30.0, pitch = 50.0;
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(0.5, Vector3d::UnitX()).toRotationMatrix();
  const Vector3d o(0, 0, 620);
  const auto truth = synth::curve(
      [&](double a) { return Vector3d(o + rot * Vector3d(R * std::cos(a), R * std::sin(a), pitch * a / (2 * M_PI))); },
      0.0, 1.7 * M_PI, 600);
  synth::Scene scene;
  scene.add_tube(truth, r, 0);
  const synth::Scan scan = synth::render(scene);
  const ewis::KdTree tree(scan.cloud.points);
  const ewis::TubeTrace t = ewis::trace_tube(scan.cloud, tree, surface_seed(truth[150], r), {});
  const Metrics m = measure(t, truth, r);
  print("helix", t, m);
  ASSERT_TRUE(t.found);
  EXPECT_GE(m.coverage, 0.95);
  EXPECT_LE(m.rms, 0.3);
  EXPECT_LE(std::abs(m.diameter_err_pct), 3.0);
}

TEST(TraceTube, TubeEndingAtABoxStopsThere) {
  const double r = 5.0;
  const Vector3d o(0, 0, 600);
  const auto truth = synth::line(o + Vector3d(-100, 0, 0), o + Vector3d(0, 0, 0));
  synth::Scene scene;
  scene.add_tube(truth, r, 0);
  const Vector3d lo = o + Vector3d(0, -20, -20), hi = o + Vector3d(40, 20, 20);
  scene.add_box(lo, hi, 1);
  const synth::Scan scan = synth::render(scene);
  const ewis::KdTree tree(scan.cloud.points);
  ewis::TubeParams p;
  p.stop_at = [&](const Vector3d& q) {
    return (q.array() >= lo.array() - 1.0).all() && (q.array() <= hi.array() + 1.0).all();
  };
  const ewis::TubeTrace t = ewis::trace_tube(scan.cloud, tree, surface_seed(o + Vector3d(-50, 0, 0), r), p);
  const Metrics m = measure(t, truth, r);
  print("box-stop", t, m);
  ASSERT_TRUE(t.found);
  EXPECT_GE(m.coverage, 0.95);
  const bool stop_front = t.end_reason_front == "stop region", stop_back = t.end_reason_back == "stop region";
  EXPECT_TRUE(stop_front || stop_back);
  for (const auto& s : t.segments) EXPECT_LE(s.cylinder.end.x(), o.x() + 0.5);
  EXPECT_LE(wrong_fraction(t, scan, 0), 0.01);
  // without the stop region the box face still ends the trace (the data change, not jump onto the box)
  const ewis::TubeTrace t2 = ewis::trace_tube(scan.cloud, tree, surface_seed(o + Vector3d(-50, 0, 0), r), {});
  print("box-free", t2, measure(t2, truth, r));
  for (const auto& s : t2.segments) EXPECT_LE(s.cylinder.end.x(), o.x() + r);
  EXPECT_LE(wrong_fraction(t2, scan, 0), 0.02);
}

TEST(TraceTube, TwoSeedsGiveTheSameTubeAndRunsAreDeterministic) {
  const double r = 5.0;
  const Vector3d dir = Vector3d(1, -0.2, 0.1).normalized();
  const Vector3d mid(0, 10, 610);
  const auto truth = synth::line(mid - dir * 80, mid + dir * 80);
  synth::Scene scene;
  scene.add_tube(truth, r, 0);
  const synth::Scan scan = synth::render(scene);
  const ewis::KdTree tree(scan.cloud.points);
  const ewis::TubeTrace t1 = ewis::trace_tube(scan.cloud, tree, surface_seed(mid - dir * 40, r), {});
  const ewis::TubeTrace t2 = ewis::trace_tube(scan.cloud, tree, surface_seed(mid + dir * 50, r), {});
  ASSERT_TRUE(t1.found && t2.found);
  std::vector<std::uint32_t> common;
  std::set_intersection(t1.points.begin(), t1.points.end(), t2.points.begin(), t2.points.end(), std::back_inserter(common));
  const double jaccard = static_cast<double>(common.size()) / (t1.points.size() + t2.points.size() - common.size());
  std::printf("[two-seeds] jaccard %.4f len %.2f %.2f r %.3f %.3f\n", jaccard, t1.length_mm, t2.length_mm, t1.radius_mm, t2.radius_mm);
  EXPECT_GE(jaccard, 0.97);
  EXPECT_NEAR(t1.length_mm, t2.length_mm, 2.0);
  EXPECT_NEAR(t1.radius_mm, t2.radius_mm, 0.05);
  const ewis::TubeTrace t3 = ewis::trace_tube(scan.cloud, tree, surface_seed(mid - dir * 40, r), {});
  EXPECT_EQ(t1.points, t3.points);
  ASSERT_EQ(t1.centerline.size(), t3.centerline.size());
  for (std::size_t i = 0; i < t1.centerline.size(); ++i) EXPECT_EQ(t1.centerline[i], t3.centerline[i]);
}

TEST(TraceTube, NoTubeAtTheSeed) {
  synth::Scene scene;
  const Vector3d c(0, 0, 600);
  scene.add_rect(c + Vector3d(-50, -50, 0), Vector3d(100, 0, 0), Vector3d(0, 100, 10), 0);
  const synth::Scan scan = synth::render(scene);
  const ewis::KdTree tree(scan.cloud.points);
  const ewis::TubeTrace t = ewis::trace_tube(scan.cloud, tree, c, {});
  print("no-tube", t, measure(t, {c, c + Vector3d(1, 0, 0)}, 1.0));
  EXPECT_FALSE(t.found);
  ewis::Cloud empty;
  const ewis::KdTree et(empty.points);
  EXPECT_FALSE(ewis::trace_tube(empty, et, c, {}).found);
}

// A thin cable lying 8 mm beside its CAD (an as-built route off the nominal one by more than its radius, as
// where a clearance defect pushed it): the spheres of the cable radius around the CAD points hold none of it.
// The second pass looks seed_search_mm from them; a plate under the cable, marked unusable as a rigid CAD
// element would be, is never taken for it.
TEST(TraceCable, CableDisplacedFromItsCadByMoreThanItsRadius) {
  const double r = 1.7;
  const Vector3d dir = Vector3d(1, 0.3, 0).normalized();
  const Vector3d mid(0, 0, 600);
  const auto truth = synth::line(mid - dir * 60, mid + dir * 60);
  synth::Scene scene;
  scene.add_tube(truth, r, 0);
  scene.add_rect(mid + Vector3d(-80, -40, r + 0.5), Vector3d(160, 0, 0), Vector3d(0, 80, 0), 1);
  const synth::Scan scan = synth::render(scene);
  const ewis::KdTree tree(scan.cloud.points);
  std::vector<std::uint8_t> usable(scan.cloud.size(), 1);
  for (std::size_t i = 0; i < usable.size(); ++i) usable[i] = scan.label[i] != 1;
  std::vector<Vector3d> cad;
  const Vector3d e1 = dir.cross(Vector3d::UnitZ()).normalized(), e2 = dir.cross(e1);
  const Vector3d off = 8.0 * e1;
  for (std::size_t i = 0; i < truth.size(); i += 2)
    for (int k = 0; k < 8; ++k) cad.push_back(truth[i] + off + r * (std::cos(k * M_PI / 4) * e1 + std::sin(k * M_PI / 4) * e2));
  ewis::TubeParams params;
  params.usable = &usable;
  params.has_sensor = true;
  params.sensor_position = Vector3d::Zero();
  EXPECT_FALSE(ewis::trace_cable(scan.cloud, tree, cad, r, params).found) << "first pass alone";
  params.seed_search_mm = 15.0;
  const ewis::TubeTrace t = ewis::trace_cable(scan.cloud, tree, cad, r, params);
  const Metrics m = measure(t, truth, r);
  print("displaced cable", t, m);
  ASSERT_TRUE(t.found);
  EXPECT_GE(m.coverage, 0.95);
  EXPECT_LE(m.rms, 0.3);
  EXPECT_LE(std::abs(m.diameter_err_pct), 8.0);
  // the same CAD over the bare plate (no cable anywhere near): nothing
  synth::Scene bare;
  bare.add_rect(mid + Vector3d(-80, -40, r + 0.5), Vector3d(160, 0, 0), Vector3d(0, 80, 0), 1);
  const synth::Scan plate = synth::render(bare);
  const ewis::KdTree plate_tree(plate.cloud.points);
  std::vector<std::uint8_t> plate_usable(plate.cloud.size(), 1);
  for (std::size_t i = 0; i < plate_usable.size(); ++i) plate_usable[i] = plate.label[i] != 1;
  params.usable = &plate_usable;
  EXPECT_FALSE(ewis::trace_cable(plate.cloud, plate_tree, cad, r, params).found);
}

TEST(TraceCable, StartsFromTheRegisteredCadPoints) {
  // paper 4.2.1: CAD cable sample points, 2 mm off the scanned cable (registration error), start the trace
  const double r = 5.0;
  const Vector3d dir = Vector3d(1, 0.2, -0.1).normalized();
  const Vector3d mid(0, 0, 600);
  const auto truth = synth::line(mid - dir * 70, mid + dir * 70);
  synth::Scene scene;
  scene.add_tube(truth, r, 0);
  const synth::Scan scan = synth::render(scene);
  const ewis::KdTree tree(scan.cloud.points);
  std::vector<Vector3d> cad;
  const Vector3d off(0, 1.5, 1.0);
  for (std::size_t i = 0; i < truth.size(); i += 4)
    for (int k = 0; k < 8; ++k) {
      const Vector3d e1 = dir.cross(Vector3d::UnitZ()).normalized(), e2 = dir.cross(e1);
      cad.push_back(truth[i] + off + r * (std::cos(k * M_PI / 4) * e1 + std::sin(k * M_PI / 4) * e2));
    }
  const ewis::TubeTrace t = ewis::trace_cable(scan.cloud, tree, cad, r, {});
  const Metrics m = measure(t, truth, r);
  print("cable", t, m);
  ASSERT_TRUE(t.found);
  EXPECT_GE(m.coverage, 0.95);
  EXPECT_LE(m.rms, 0.3);
  EXPECT_LE(std::abs(m.diameter_err_pct), 3.0);
  EXPECT_GE(ewis::chain_coverage(t, truth, 1.0), 0.95);
}

}  // namespace

// run_support: a trace on a tube seen whole holds about the points the tube shows (its width seen over the resolution
// squared, per mm across the rays); the same chain holding a tenth of them (a trace on stray points) reads a tenth.
TEST(TraceTube, RunSupportCountsThePointsATubeShows) {
  for (const double r : {2.5, 4.5}) {
    const synth::Scan scan = oblique_tube_scan(r);
    const ewis::KdTree tree(scan.cloud.points);
    const ewis::TubeTrace t = ewis::trace_tube(scan.cloud, tree, surface_seed(kObliqueMid, r), {});
    ASSERT_TRUE(t.found) << "r " << r;
    // the resolution as the pipeline measures it (the median nearest-neighbour distance)
    const double res = ewis::spatial_resolution(tree).median_mm;
    ASSERT_GT(res, 0.0);
    const double whole = ewis::run_support(t, Vector3d::Zero(), res);
    EXPECT_GT(whole, 0.6) << "r " << r;
    EXPECT_LT(whole, 1.7) << "r " << r;
    ewis::TubeTrace sparse = t;
    sparse.points.clear();
    for (std::size_t k = 0; k < t.points.size(); k += 10) sparse.points.push_back(t.points[k]);
    EXPECT_NEAR(ewis::run_support(sparse, Vector3d::Zero(), res), whole / 10, 0.01 * whole) << "r " << r;
    // the same points judged from a sensor looking along the tube: it would show far fewer, so they read far more
    EXPECT_GT(ewis::run_support(t, kObliqueMid + kObliqueDir * 1000.0, res), 10.0 * whole) << "r " << r;
  }
}
