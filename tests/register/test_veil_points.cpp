// Veils of mixed pixels: found by their normals containing the viewing ray; and the plate-and-wall scene where
// they dragged the registration along the plate (issue: scene_010 converged 15 mm off).
#include <gtest/gtest.h>

#include <iostream>
#include <random>

#include "ewis/register/scan_to_cad.hpp"
#include "ewis/register/veil_points.hpp"
#include "synthetic_scene.hpp"

namespace ewis {
namespace {

// In the sensor frame (the sensor at the origin, looking along +z): a plate at depth 600 and a veil hanging from
// an edge at depth 560 towards the plate, on the rays through x = 0.
TEST(VeilPoints, DropsTheVeilKeepsTheSurfaces) {
  std::vector<Eigen::Vector3f> pts;
  for (int i = -60; i <= 60; ++i)
    for (int j = -60; j <= 60; ++j) pts.emplace_back(2.0f * i, 2.0f * j, 600.0f);
  const std::size_t surface = pts.size();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.15, 0.85);
  for (int j = -200; j <= 200; ++j) {  // one mixed pixel per 0.3 mm of edge
    const Eigen::Vector3d ray = Eigen::Vector3d(0.0, 0.3 * j, 560.0).normalized();
    const double d = 560.0 / ray.z() + u(rng) * (600.0 - 560.0) / ray.z();
    pts.push_back((d * ray).cast<float>());
  }
  const std::vector<std::uint32_t> keep = points_off_veils(pts, Eigen::Vector3d::Zero());
  std::size_t kept_surface = 0, kept_veil = 0;
  for (std::uint32_t i : keep) (i < surface ? kept_surface : kept_veil)++;
  EXPECT_GE(kept_surface, surface * 98 / 100);
  EXPECT_LE(kept_veil, (pts.size() - surface) / 20);
}

// A plate with a tall wall along its -y edge, another along its +x edge and one block in a corner: the sensor
// looks over the first wall, so that wall's inner face is hidden and its top edge is a depth edge whose mixed
// pixels hang ~1-3 mm beside that face. Only the block's faces pin the pose along y.
Scene wall_scene() {
  Scene s;
  using V = Eigen::Vector3d;
  test::add_mesh(s, "plate", make_box(V(0, 0, -6), V(400, 300, 0)));
  test::add_mesh(s, "wall", make_box(V(0, 0, 0), V(400, 10, 40)));
  test::add_mesh(s, "wall_x", make_box(V(390, 10, 0), V(400, 300, 40)));
  test::add_mesh(s, "block", make_box(V(20, 230, 0), V(70, 280, 25)));
  return s;
}

test::SimScan wall_scan(std::uint64_t seed) {
  const Scene scene = wall_scene();
  const Cloud all = test::sample_scene(scene, 1.5, seed);
  const Eigen::Vector3d eye(200.0, -40.0, 600.0);
  const Pose cam = look_at(eye, Eigen::Vector3d(200.0, 150.0, 0.0), Eigen::Vector3d::UnitY());
  const Pose cad_to_cam = cam.inverse();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.2);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  test::SimScan out;
  out.camera_to_cad = cam;
  const double cos_limit = std::cos(75.0 * M_PI / 180.0);  // no returns beyond 75 deg of incidence
  auto measure = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d pc = cad_to_cam * p;
    out.scan.points.push_back((pc + noise(rng) * pc.normalized()).cast<float>());
  };
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Eigen::Vector3d p = all.points[i].cast<double>();
    const Eigen::Vector3d to_eye = (eye - p).normalized();
    if (all.normals[i].cast<double>().dot(to_eye) < cos_limit) continue;
    // Hidden behind the wall: the ray to the eye crosses the wall's inner face plane below its top.
    if (p.y() > 10.0) {
      const double s = (10.0 - p.y()) / (eye.y() - p.y());
      if (p.z() + s * (eye.z() - p.z()) < 40.0) continue;
    }
    measure(p);
  }
  // Mixed pixels of the wall's top inner edge: on the ray through the edge, between the edge and the plate.
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector3d edge(400.0 * u(rng), 10.0, 40.0);
    const Eigen::Vector3d dir = edge - eye;
    const double to_plate = (0.0 - eye.z()) / dir.z();  // ray parameter at z = 0 (the edge is at 1)
    measure(eye + (1.0 + (0.15 + 0.7 * u(rng)) * (to_plate - 1.0)) * dir);
  }
  return out;
}

TEST(ScanToCad, WallVeilDoesNotDragThePoseAlongThePlate) {
  const CadTarget t = build_cad_target(wall_scene(), InspectionPlan{}, CadTargetParams{});
  const Eigen::Vector3d c(200, 150, 10);
  auto error_mm = [&](const ScanToCadResult& r, const test::SimScan& sim) {
    const Pose d = r.registration.source_to_target * sim.camera_to_cad.inverse();
    return (d * c - c).norm();
  };
  for (std::uint64_t seed = 1; seed <= 2; ++seed) {
    const test::SimScan sim = wall_scan(seed);
    const Pose init = Eigen::Translation3d(c) * test::perturbation(seed, 1.0, 15.0) * Eigen::Translation3d(-c) *
                      sim.camera_to_cad;
    const ScanToCadResult r = register_scan_to_cad(sim.scan, t, init);
    SCOPED_TRACE("seed " + std::to_string(seed));
    EXPECT_TRUE(r.valid);
    EXPECT_LT(rotation_error_deg(r.registration.source_to_target, sim.camera_to_cad), 0.1);
    EXPECT_LT(error_mm(r, sim), 0.3);
    if (seed == 1) {  // the scene shows the failure: with its veil the pose ends ~1 mm off along y
      ScanToCadParams keep_veils;
      keep_veils.drop_veils = false;
      const double with_veil = error_mm(register_scan_to_cad(sim.scan, t, init, keep_veils), sim);
      std::cout << "wall veil: dropped " << error_mm(r, sim) << " mm, kept " << with_veil << " mm\n";
      EXPECT_LT(error_mm(r, sim), with_veil);
    }
  }
}

}  // namespace
}  // namespace ewis
