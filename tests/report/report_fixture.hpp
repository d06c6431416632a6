#pragma once
// A small hand-built inspection for the report tests: a plate, two cables (one bent too tightly, one too
// close to a pipe) and a foreign sphere, "scanned" by ray casting the CAD from a sensor 600 mm above, so
// every point's label (cable, interference, rest) is known exactly.
#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <string>

#include "ewis/inspect/pipeline.hpp"
#include "ewis/raycast/raycaster.hpp"
#include "ewis/scene/primitives.hpp"
#include "ewis/scene/scene.hpp"
#include "test_tmp.hpp"

namespace ewis::test {

inline std::string test_dir(const std::string& name) {
  const std::string dir = (own_tmp_dir("report") / name).string();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

struct ReportFixture {
  Scene scene;
  InspectionPlan plan;
  InspectionResult result;
  std::vector<Eigen::Vector3d> route_a, route_b;
};

inline void add_mesh(Scene& s, const std::string& name, const Mesh& m) { add_element(s, name, m.vertices, m.triangles); }

// cable_A: straight along x, then a 90-degree arc of radius 30 mm (bend defect); cable_B: straight along y
// 2 mm above a pipe (clearance defect); a small sphere beside cable_B (foreign object).
inline ReportFixture make_fixture(bool with_defects = true) {
  ReportFixture f;
  const double ra = 4.0, rb = 3.0;
  for (int i = 0; i <= 40; ++i) f.route_a.push_back({-120.0 + 3.0 * i, -40.0, ra});
  for (int i = 1; i <= 30; ++i) {
    const double a = (M_PI / 2) * i / 30.0;
    f.route_a.push_back({0.0 + 30.0 * std::sin(a), -40.0 + 30.0 * (1 - std::cos(a)), ra});
  }
  for (int i = 1; i <= 20; ++i) f.route_a.push_back({30.0, -10.0 + 3.0 * i, ra});
  for (int i = 0; i <= 50; ++i) f.route_b.push_back({80.0, -100.0 + 4.0 * i, 20.0});
  add_mesh(f.scene, "plate", make_box({-150, -120, -5}, {150, 120, 0}));
  add_mesh(f.scene, "cable_A", make_tube(f.route_a, ra));
  add_mesh(f.scene, "cable_B", make_tube(f.route_b, rb));
  add_mesh(f.scene, "pipe_1", make_cylinder({40, 0, 12}, {120, 0, 12}, 5.0));  // top at 17, cable B bottom at 17+... gap 0
  add_mesh(f.scene, "sphere_x", make_sphere({95, 40, 20}, 6.0));

  PlanElement a;
  a.name = "cable_A";
  a.kind = ElementKind::Cable;
  a.diameter_mm = 2 * ra;
  a.min_bend_radius_mm = 48.0;
  a.clearance_mm = 2.0;
  PlanElement b = a;
  b.name = "cable_B";
  b.diameter_mm = 2 * rb;
  b.min_bend_radius_mm.reset();
  b.min_bend_ratio = 5.0;
  b.clearance_mm = 3.0;
  b.bend_reference = BendReference::Inner;
  f.plan.elements = {a, b};
  for (const char* n : {"plate", "pipe_1"}) {
    PlanElement r;
    r.name = n;
    f.plan.elements.push_back(r);
  }
  f.plan.sensor.width_px = 640;
  f.plan.sensor.height_px = 512;

  InspectionResult& r = f.result;
  r.scan_to_cad = look_at({0, 0, 600}, {0, 0, 0}, Eigen::Vector3d::UnitY());
  r.sensor_position = r.scan_to_cad.translation();
  r.optical_axis = r.scan_to_cad.linear().col(2);
  r.registration_rmse_mm = 0.21;
  r.registration_fitness = 0.93;
  r.registration_converged = true;
  r.resolution_mm = 2.0 * 600.0 * std::tan(29.0 * M_PI / 180.0) / 640.0;  // the pixel footprint on the plate
  r.timings = {{"filter", 0.5}, {"register", 1.25}};

  // The "scan": one ray per pixel of the sensor, hits in CAD coordinates, labelled by element.
  const Raycaster caster(f.scene);
  const Render ren = render(caster, f.plan.sensor.camera(), r.scan_to_cad);
  const Eigen::Matrix3d rot = r.scan_to_cad.linear();
  std::vector<std::uint32_t> pts_a, pts_b, pts_pipe, pts_sphere;
  for (int y = 0; y < ren.height_px; ++y)
    for (int x = 0; x < ren.width_px; ++x) {
      const std::size_t k = std::size_t(y) * ren.width_px + x;
      if (ren.element[k] == kNoElement) continue;
      const Eigen::Vector3d dir = (rot * f.plan.sensor.camera().pixel_ray(x, y)).normalized();
      const Eigen::Vector3d p = r.sensor_position + dir * double(ren.distance_mm[k]);
      const auto idx = static_cast<std::uint32_t>(r.cloud.points.size());
      r.cloud.points.push_back(p.cast<float>());
      const std::string& name = f.scene.elements[ren.element[k]].name;
      if (name == "cable_A") pts_a.push_back(idx);
      if (name == "cable_B") pts_b.push_back(idx);
      if (name == "pipe_1" && std::abs(p.x() - 80.0) < 12.0) pts_pipe.push_back(idx);
      if (name == "sphere_x") pts_sphere.push_back(idx);
    }
  r.scan_points = r.filtered_points = r.cloud.size();

  auto chain = [](const std::vector<Eigen::Vector3d>& route, double radius, std::size_t every) {
    TubeTrace t;
    t.found = true;
    t.radius_mm = radius;
    for (std::size_t i = 0; i + 1 < route.size(); i += every) {
      const std::size_t j = std::min(i + every, route.size() - 1);
      SubCable s;
      s.cylinder = Cylinder{route[i], route[j], radius};
      s.points = 100;
      t.segments.push_back(s);
    }
    t.centerline = route;
    t.length_mm = polyline_length(route);
    return t;
  };

  CableInspection ca;
  ca.name = "cable_A";
  ca.element = f.scene.find("cable_A");
  ca.nominal_diameter_mm = 2 * ra;
  ca.found = true;
  ca.diameter_mm = 2 * ra - 0.05;
  ca.trace = chain(f.route_a, ra, 3);
  ca.trace.points = pts_a;
  ca.length_mm = ca.trace.length_mm;
  ca.min_bend_radius_mm = with_defects ? 30.4 : 60.0;
  ca.min_bend_radius_inner_mm = *ca.min_bend_radius_mm - ra;
  ca.min_bend_location = Eigen::Vector3d(21.2, -31.2, ra);
  ca.bend.min_radius_mm = ca.min_bend_radius_mm;
  ca.bend.circle_center = Eigen::Vector3d(0, -10, ra);
  ca.bend.circle_normal = Eigen::Vector3d::UnitZ();
  ca.paper_bend.radius_mm = 31.7;
  ca.allowed_bend_radius_mm = 48.0;
  ca.clearance_mm = 2.0;
  ca.bend_ok = !with_defects;
  ca.clearance_ok = true;

  CableInspection cb;
  cb.name = "cable_B";
  cb.element = f.scene.find("cable_B");
  cb.nominal_diameter_mm = 2 * rb;
  cb.found = true;
  cb.diameter_mm = 2 * rb + 0.04;
  cb.trace = chain(f.route_b, rb, 4);
  cb.trace.segments[10].bridged = true;
  cb.trace.points = pts_b;
  cb.length_mm = cb.trace.length_mm;
  cb.allowed_bend_radius_mm = 15.0;
  cb.bend_reference = BendReference::Inner;
  cb.clearance_mm = 3.0;
  cb.bend_ok = true;
  cb.clearance_ok = !with_defects;
  if (with_defects) {
    Interference pipe;
    pipe.with = "pipe_1";
    pipe.with_element = f.scene.find("pipe_1");
    pipe.min_distance_mm = 0.0;
    pipe.points = pts_pipe;
    pipe.center = Eigen::Vector3d(80, 0, 17);
    pipe.closest_on_cable = Eigen::Vector3d(80, 0, 17);
    pipe.closest_on_other = Eigen::Vector3d(80, 0, 17);
    Interference foreign;
    foreign.min_distance_mm = 1.2;
    foreign.points = pts_sphere;
    foreign.center = Eigen::Vector3d(95, 40, 24);
    foreign.closest_on_cable = Eigen::Vector3d(83, 40, 20);
    foreign.closest_on_other = Eigen::Vector3d(89, 40, 20);
    cb.interferences = {pipe, foreign};
  }
  r.cables = {ca, cb};
  r.rigid = {{"plate", f.scene.find("plate"), 1000}, {"pipe_1", f.scene.find("pipe_1"), 100}};
  r.pass = !with_defects;
  return f;
}

}  // namespace ewis::test
