#pragma once
// A CAD-like rigid scene (plate, blocks, L-brackets, a connector, one cable) and simulated partial scans of it
// with known pose, noise and outliers: the truth for the register tests.
#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "ewis/core/cloud.hpp"
#include "ewis/core/pose.hpp"
#include "ewis/io/plan_file.hpp"
#include "ewis/scene/primitives.hpp"
#include "ewis/scene/scene.hpp"

namespace ewis::test {

inline void add_mesh(Scene& s, const std::string& name, const Mesh& m) { add_element(s, name, m.vertices, m.triangles); }

inline std::vector<Eigen::Vector3d> cable_route(double dy, double dz) {
  std::vector<Eigen::Vector3d> c;
  for (int i = 0; i <= 120; ++i) {
    const double x = 20.0 + 3.0 * i;
    c.emplace_back(x, 140.0 + dy + 25.0 * std::sin(x / 60.0), 12.0 + dz);
  }
  return c;
}

// The nominal CAD; `cable_dy/dz` move the cable (the as-built cable of a scan differs from the CAD's).
inline Scene make_scene(double cable_dy = 0.0, double cable_dz = 0.0) {
  Scene s;
  using V = Eigen::Vector3d;
  add_mesh(s, "plate", make_box(V(0, 0, -5), V(400, 300, 0)));
  add_mesh(s, "block_1", make_box(V(40, 40, 0), V(110, 85, 45)));
  add_mesh(s, "block_2", make_box(V(250, 190, 0), V(300, 265, 70)));
  add_mesh(s, "block_3", make_box(V(300, 30, 0), V(370, 60, 25)));
  Mesh b1 = make_box(V(150, 210, 0), V(156, 270, 60));
  Mesh b2 = make_box(V(150, 210, 54), V(205, 270, 60));
  add_mesh(s, "bracket_1", b1);
  add_mesh(s, "bracket_1b", b2);
  add_mesh(s, "bracket_2", make_box(V(60, 230, 0), V(66, 280, 40)));
  add_mesh(s, "connector_J1", make_cylinder(V(200, 80, 0), V(200, 80, 35), 14.0, 48));
  add_mesh(s, "cable_A", make_tube(cable_route(cable_dy, cable_dz), 5.0, 24));
  return s;
}

inline InspectionPlan make_plan() {
  InspectionPlan p;
  PlanElement c;
  c.name = "cable_A";
  c.kind = ElementKind::Cable;
  c.diameter_mm = 10.0;
  c.min_bend_radius_mm = 50.0;
  p.elements.push_back(c);
  return p;
}

// Area-weighted surface samples of every element (the test's own sampler, independent of sample/).
inline Cloud sample_scene(const Scene& s, double spacing_mm, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Cloud c;
  for (const auto& tri : s.triangles) {
    const Eigen::Vector3d a = s.vertices[tri[0]].cast<double>(), b = s.vertices[tri[1]].cast<double>(),
                          d = s.vertices[tri[2]].cast<double>();
    const Eigen::Vector3d cr = (b - a).cross(d - a);
    const double area = 0.5 * cr.norm();
    if (area <= 0) continue;
    const double expected = area / (spacing_mm * spacing_mm);
    int n = static_cast<int>(expected);
    if (u(rng) < expected - n) ++n;
    for (int k = 0; k < n; ++k) {
      double r1 = u(rng), r2 = u(rng);
      if (r1 + r2 > 1) {
        r1 = 1 - r1;
        r2 = 1 - r2;
      }
      c.points.push_back((a + r1 * (b - a) + r2 * (d - a)).cast<float>());
      c.normals.push_back(cr.normalized().cast<float>());
    }
  }
  return c;
}

struct SimScan {
  Cloud scan;         // sensor frame
  Pose camera_to_cad;  // truth
};

// A partial view from a sensor above the scene: surfaces facing the sensor, inside a window of the scene,
// with Gaussian noise along the ray and uniform outliers in the view volume.
inline SimScan simulate_scan(const Scene& as_built, std::uint64_t seed, double noise_mm = 0.2,
                             double outlier_fraction = 0.1, double spacing_mm = 2.0) {
  std::mt19937_64 rng(seed * 7919 + 1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> g(0.0, noise_mm);
  const Cloud all = sample_scene(as_built, spacing_mm, seed);
  const Eigen::Vector3d eye(150.0 + 60.0 * u(rng), 120.0 + 40.0 * u(rng), 520.0);
  const Pose cam = look_at(eye, Eigen::Vector3d(200.0 + 20 * u(rng), 150.0, 0.0), Eigen::Vector3d::UnitY());
  const Pose cad_to_cam = cam.inverse();
  const double xmax = 330.0 + 50.0 * u(rng);  // the view sees only part of the scene
  SimScan out;
  out.camera_to_cad = cam;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Eigen::Vector3d p = all.points[i].cast<double>();
    const Eigen::Vector3d to_eye = eye - p;
    if (all.normals[i].cast<double>().dot(to_eye) <= 0.05 * to_eye.norm()) continue;
    if (p.x() > xmax) continue;
    Eigen::Vector3d pc = cad_to_cam * p;
    pc += g(rng) * pc.normalized();  // noise along the camera ray
    out.scan.points.push_back(pc.cast<float>());
  }
  const std::size_t n_out = static_cast<std::size_t>(outlier_fraction * out.scan.size());
  for (std::size_t i = 0; i < n_out; ++i) {
    const Eigen::Vector3d p(u(rng) * 400, u(rng) * 300, u(rng) * 120 - 10);
    out.scan.points.push_back((cad_to_cam * p).cast<float>());
  }
  return out;
}

// A perturbation of up to max_deg about a random axis and max_mm along a random direction.
inline Pose perturbation(std::uint64_t seed, double max_deg, double max_mm) {
  std::mt19937_64 rng(seed * 104729 + 3);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.5, 1.0);
  const Eigen::Vector3d axis = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
  const Eigen::Vector3d dir = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
  return make_pose(axis, max_deg * u(rng), dir * max_mm * u(rng));
}

// Error of an estimated scan_to_cad pose, measured at the scene's centre (as the registration goals measure it).
struct PoseError {
  double deg, mm;
};
inline PoseError pose_error(const Pose& est, const Pose& truth) {
  const Eigen::Vector3d c(200, 150, 20);
  return {rotation_error_deg(est, truth), ((est * truth.inverse()) * c - c).norm()};
}

// `truth` perturbed by perturbation(seed, deg, mm) about the scene's centre.
inline Pose off_at_scene(const Pose& truth, std::uint64_t seed, double deg, double mm) {
  const Eigen::Vector3d c(200, 150, 20);
  return Eigen::Translation3d(c) * perturbation(seed, deg, mm) * Eigen::Translation3d(-c) * truth;
}

}  // namespace ewis::test
