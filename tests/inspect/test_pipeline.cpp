#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <random>

#include "ewis/core/error.hpp"
#include "ewis/inspect/pipeline.hpp"
#include "ewis/scene/primitives.hpp"
#include "paths.hpp"

using namespace ewis;

namespace {

// A synthetic inspection: a cable (d 8) lying 20 mm over a plate, straight - arc R 60 (90 deg) - straight,
// a bracket 2 mm beside its first straight, seen by a sensor 600 mm above; points every ~0.5 mm with 0.05 mm
// noise on the surfaces that face the sensor. The scan is in the sensor's frame.
struct Synthetic {
  Scene scene;
  InspectionPlan plan;
  Cloud scan;
  Pose camera_to_cad;
  std::vector<Eigen::Vector3d> centreline;  // the cable's, 1 mm steps
};

Synthetic make_synthetic(double arc_radius_mm = 60.0, double arc_deg = 90.0) {
  Synthetic s;
  const double r = 4.0, z = 30.0;
  test::Turtle t;
  t.pos = {-120, -40, z};
  t.points = {t.pos};
  t.step = 1.0;
  t.straight(120);
  t.arc(arc_radius_mm, arc_deg, Eigen::Vector3d::UnitY());
  t.straight(100);
  s.centreline = t.points;
  const auto& cl = s.centreline;
  const Mesh tube = make_tube(cl, r, 32);
  add_element(s.scene, "cable_A", tube.vertices, tube.triangles);
  const Mesh plate = make_box({-200, -150, 0}, {200, 250, 10});
  add_element(s.scene, "plate", plate.vertices, plate.triangles);
  // bracket beside the first straight (y = -40), 2 mm from the cable's surface, from the plate up to z 40
  const Mesh bracket = make_box({-80, -40 - r - 2.0 - 10.0, 10}, {-60, -40 - r - 2.0, 40});
  add_element(s.scene, "bracket", bracket.vertices, bracket.triangles);

  PlanElement cable;
  cable.name = "cable_A";
  cable.kind = ElementKind::Cable;
  cable.diameter_mm = 2 * r;
  cable.min_bend_radius_mm = 40.0;
  cable.clearance_mm = 3.0;
  s.plan.elements = {cable};
  PlanElement plate_e;
  plate_e.name = "plate";
  PlanElement bracket_e;
  bracket_e.name = "bracket";
  s.plan.elements.push_back(plate_e);
  s.plan.elements.push_back(bracket_e);

  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 0.05);
  std::vector<Eigen::Vector3d> pts;
  // cable: rings around the centreline, the upper half (seen from above)
  for (std::size_t i = 0; i + 1 < cl.size(); ++i) {
    const Eigen::Vector3d a = cl[i], b = cl[i + 1];
    const Eigen::Vector3d ax = (b - a).normalized();
    const Eigen::Vector3d u = ax.cross(Eigen::Vector3d::UnitZ()).normalized(), v = ax.cross(u);
    for (double f = 0; f < 1.0; f += 0.5)
      for (int j = 0; j < 52; ++j) {
        const double phi = 2 * M_PI * j / 52;
        const Eigen::Vector3d n = std::cos(phi) * u + std::sin(phi) * v;
        if (n.z() < 0.05) continue;
        pts.push_back(a + f * (b - a) + r * n);
      }
  }
  // plate top, except under the cable (its shadow) and the bracket
  for (double x = -160; x <= 160; x += 0.7)
    for (double y = -100; y <= 150; y += 0.7) {
      const Eigen::Vector3d p(x, y, 10);
      bool hidden = false;
      for (const auto& c : cl)
        if (std::hypot(c.x() - x, c.y() - y) < r) {
          hidden = true;
          break;
        }
      if (x >= -80 && x <= -60 && y >= -40 - r - 12 && y <= -40 - r - 2) hidden = true;
      if (!hidden) pts.push_back(p);
    }
  // bracket top, and its face toward the cable (the sensor, 60 mm to that side, sees it at a grazing angle)
  for (double x = -80; x <= -60; x += 0.5)
    for (double y = -40 - r - 12; y <= -40 - r - 2 + 1e-9; y += 0.5) pts.emplace_back(x, y, 40);
  for (double x = -80; x <= -60; x += 0.5)
    for (double zz = 10; zz <= 40; zz += 0.5) pts.emplace_back(x, -40 - r - 2.0, zz);
  s.camera_to_cad = look_at({0, 20, 620}, {0, 20, 0}, Eigen::Vector3d::UnitY());
  const Pose cad_to_camera = s.camera_to_cad.inverse();
  for (const auto& p : pts) {
    const Eigen::Vector3d q = p + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    s.scan.points.push_back((cad_to_camera * q).cast<float>());
  }
  return s;
}

InspectParams fast_params() {
  InspectParams p;
  p.register_scan = false;  // the registration stage has its own tests; the true pose is given
  return p;
}

}  // namespace

TEST(Pipeline, SyntheticSceneMeasures) {
  const Synthetic s = make_synthetic();
  const InspectionResult r = inspect(s.scene, s.plan, s.scan, s.camera_to_cad, fast_params());
  ASSERT_EQ(r.cables.size(), 1u);
  const CableInspection& c = r.cables[0];
  ASSERT_TRUE(c.found);
  EXPECT_NEAR(c.diameter_mm, 8.0, 0.4);
  EXPECT_NEAR(c.length_mm, 120 + 60 * M_PI / 2 + 100, 25.0);
  ASSERT_TRUE(c.min_bend_radius_mm);
  EXPECT_NEAR(*c.min_bend_radius_mm / 60.0, 1.0, 0.05);
  EXPECT_TRUE(c.bend_ok.value_or(false));
  ASSERT_FALSE(c.interferences.empty());
  const Interference& f = c.interferences.front();
  ASSERT_TRUE(f.with.has_value());
  EXPECT_EQ(*f.with, "bracket");
  EXPECT_NEAR(f.min_distance_mm, 2.0, 0.5);
  EXPECT_EQ(c.clearance_ok, false);
  EXPECT_FALSE(r.pass);

  // report.json: the contract's fields, nulls where they belong, plan order
  const nlohmann::json j = nlohmann::json::parse(report_to_json(r, s.plan));
  EXPECT_EQ(j["verdict"], "fail");
  ASSERT_EQ(j["registration"]["transform"].size(), 4u);
  const auto& e = j["elements"][0];
  EXPECT_EQ(e["name"], "cable_A");
  EXPECT_EQ(e["kind"], "cable");
  EXPECT_TRUE(e["found"].get<bool>());
  for (const char* key : {"diameter_mm", "length_mm", "min_bend_radius_mm", "min_bend_radius_inner_mm"})
    EXPECT_TRUE(e[key].is_number()) << key;
  EXPECT_NEAR(e["min_bend_radius_inner_mm"].get<double>(),
              e["min_bend_radius_mm"].get<double>() - e["diameter_mm"].get<double>() / 2, 0.02);
  EXPECT_EQ(e["min_bend_location"].size(), 3u);
  EXPECT_EQ(e["interferences"][0]["with"], "bracket");
  EXPECT_GE(e["interferences"][0]["points"].get<int>(), 1);
  EXPECT_FALSE(e["segments"].empty());
  EXPECT_EQ(j["elements"][1]["kind"], "rigid");
}

// A cable whose last 150 mm (of 315) the scan does not show is found, traced along about half of its CAD, and warned
// about (InspectParams::min_traced_fraction); seen whole, it is traced along all of it, without the warning.
TEST(Pipeline, ACableTracedAlongLittleOfItsCadIsWarnedAbout) {
  const Synthetic s = make_synthetic();
  const auto warned = [](const InspectionResult& r) {
    return std::any_of(r.warnings.begin(), r.warnings.end(),
                       [](const std::string& w) { return w.rfind("cable_A: traced along", 0) == 0; });
  };
  const InspectionResult whole = inspect(s.scene, s.plan, s.scan, s.camera_to_cad, fast_params());
  ASSERT_TRUE(whole.cables[0].found);
  EXPECT_GT(whole.cables[0].cad_traced_fraction, 0.9);
  EXPECT_FALSE(warned(whole));
  // the scan without the cable's points near its last 150 mm
  const std::vector<Eigen::Vector3d> hidden(s.centreline.end() - 150, s.centreline.end());
  Cloud part;
  for (const Eigen::Vector3f& q : s.scan.points) {
    const Eigen::Vector3d p = s.camera_to_cad * q.cast<double>();
    if (std::none_of(hidden.begin(), hidden.end(), [&](const Eigen::Vector3d& c) { return (p - c).norm() < 5.0; }))
      part.points.push_back(q);
  }
  const InspectionResult r = inspect(s.scene, s.plan, part, s.camera_to_cad, fast_params());
  ASSERT_TRUE(r.cables[0].found);
  EXPECT_LT(r.cables[0].cad_traced_fraction, 0.7);
  EXPECT_GT(r.cables[0].cad_traced_fraction, 0.4);
  EXPECT_TRUE(warned(r));
  const nlohmann::json j = nlohmann::json::parse(report_to_json(r, s.plan));
  EXPECT_NEAR(j["elements"][0]["cad_traced_fraction"].get<double>(), r.cables[0].cad_traced_fraction, 1e-3);
}

// A short tight bend: 20 deg at R 20 mm on a d 8 cable (an arc of 7 mm, under one diameter). Circle windows
// along the centreline take in the straight runs and read it far too high; the fillet fit on the surface points
// measures it.
TEST(Pipeline, ShortTightBendFromTheSurface) {
  const Synthetic s = make_synthetic(20.0, 20.0);
  InspectParams p = fast_params();
  const InspectionResult r = inspect(s.scene, s.plan, s.scan, s.camera_to_cad, p);
  ASSERT_TRUE(r.cables[0].found);
  ASSERT_TRUE(r.cables[0].min_bend_radius_mm);
  EXPECT_NEAR(*r.cables[0].min_bend_radius_mm / 20.0, 1.0, 0.08);
  EXPECT_FALSE(r.cables[0].bend_ok.value_or(true));  // allowed 40
  p.fillet.enabled = false;
  const InspectionResult circles = inspect(s.scene, s.plan, s.scan, s.camera_to_cad, p);
  ASSERT_TRUE(circles.cables[0].min_bend_radius_mm);
  EXPECT_GT(*circles.cables[0].min_bend_radius_mm / 20.0, 1.15);
}

TEST(Pipeline, InnerReferenceAndMissingCable) {
  Synthetic s = make_synthetic();
  // allowed 57 mm: the centreline radius (~60) passes, the inner one (~56) fails
  s.plan.elements[0].min_bend_radius_mm = 57.0;
  s.plan.elements[0].clearance_mm = 0.5;  // the bracket at 2 mm is then fine
  InspectionResult r = inspect(s.scene, s.plan, s.scan, s.camera_to_cad, fast_params());
  ASSERT_TRUE(r.cables[0].found);
  EXPECT_TRUE(r.cables[0].bend_ok.value_or(false));
  EXPECT_TRUE(r.cables[0].clearance_ok.value_or(false));
  EXPECT_TRUE(r.pass);
  s.plan.elements[0].bend_reference = BendReference::Inner;
  r = inspect(s.scene, s.plan, s.scan, s.camera_to_cad, fast_params());
  EXPECT_FALSE(r.cables[0].bend_ok.value_or(true));
  EXPECT_FALSE(r.pass);

  // A cable of the plan that the scan does not show: found false, nulls, verdict fail.
  const Mesh ghost = make_cylinder({-100, 200, 30}, {100, 200, 30}, 4.0);
  add_element(s.scene, "cable_G", ghost.vertices, ghost.triangles);
  PlanElement g = s.plan.elements[0];
  g.name = "cable_G";
  s.plan.elements.push_back(g);
  r = inspect(s.scene, s.plan, s.scan, s.camera_to_cad, fast_params());
  ASSERT_EQ(r.cables.size(), 2u);
  EXPECT_FALSE(r.cables[1].found);
  EXPECT_FALSE(r.pass);
  const nlohmann::json j = nlohmann::json::parse(report_to_json(r, s.plan));
  const auto& e = j["elements"].back();
  EXPECT_EQ(e["name"], "cable_G");
  EXPECT_FALSE(e["found"].get<bool>());
  for (const char* key : {"diameter_mm", "length_mm", "min_bend_radius_mm", "min_bend_location", "bend_ok",
                          "clearance_ok"})
    EXPECT_TRUE(e[key].is_null()) << key;
  EXPECT_TRUE(e["interferences"].empty());
  EXPECT_TRUE(e["segments"].empty());
}

TEST(Pipeline, ReportIndependentOfThreadCount) {
  const Synthetic s = make_synthetic();
  std::string one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = report_to_json(inspect(s.scene, s.plan, s.scan, s.camera_to_cad, fast_params()), s.plan);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = report_to_json(inspect(s.scene, s.plan, s.scan, s.camera_to_cad, fast_params()), s.plan);
  }
  EXPECT_EQ(one, two);
}

TEST(Pipeline, UnknownPlanElementIsAnInputError) {
  Synthetic s = make_synthetic();
  EXPECT_NO_THROW(check_plan_against_scene(s.plan, s.scene, "plan.json"));
  s.plan.elements[0].attached = {"nope"};
  EXPECT_THROW(check_plan_against_scene(s.plan, s.scene, "plan.json"), InputError);
  s.plan.elements[0].attached.clear();
  s.plan.elements[1].name = "missing";
  EXPECT_THROW(check_plan_against_scene(s.plan, s.scene, "plan.json"), InputError);
}
