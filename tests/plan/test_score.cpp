#include <gtest/gtest.h>

#include <cmath>

#include "ewis/plan/score.hpp"
#include "plan_scenes.hpp"

namespace ewis {
namespace {

using test::add_mesh;

// Pixels of a sphere of radius r seen from distance d on the optical axis: the cone tangent to the sphere
// has half-angle asin(r/d); its image is a disc of radius f * r / sqrt(d^2 - r^2).
double sphere_pixels(double f, double r, double d) { return M_PI * (f * r) * (f * r) / (d * d - r * r); }

TEST(Score, SphereAloneMatchesTheAnalyticAreaWithin1Percent) {
  Scene scene;
  add_mesh(scene, "ball", make_sphere(Eigen::Vector3d(5, -3, 2), 50.0, 360, 180));
  const Raycaster all(scene), only(scene, {true});
  const Camera camera{1280, 1024, 58.0};
  CandidateParams cp;
  cp.step_deg = 45;
  cp.radius_mm = 400;
  const CandidateGrid g = make_candidates(scene.elements[0].center_of_mass, cp);
  ScoreParams sp;
  auto scores = score_candidates(all, camera, 0, g.candidates, cp.radius_mm, sp);
  add_visible_fractions(only, camera, 0, g.candidates, sp, scores);
  const double truth = sphere_pixels(camera.focal_px(), 50.0, 400.0);
  ASSERT_EQ(scores.size(), g.candidates.size());
  for (std::size_t i = 0; i < scores.size(); ++i) {
    EXPECT_FALSE(scores[i].rejected) << i;
    EXPECT_NEAR(double(scores[i].score_px), truth, 0.01 * truth) << "candidate " << i;
    EXPECT_EQ(scores[i].score_px, scores[i].isolated_px);
    EXPECT_DOUBLE_EQ(scores[i].visible_fraction, 1.0);
  }
}

TEST(Score, PlateHidesOneSideAndTheBestViewsAreOnTheOther) {
  Scene scene;
  add_mesh(scene, "ball", make_sphere(Eigen::Vector3d::Zero(), 50.0, 96, 48));
  add_mesh(scene, "plate", make_box(Eigen::Vector3d(200, -400, -400), Eigen::Vector3d(210, 400, 400)));
  const Raycaster all(scene), only(scene, {true, false});
  const Camera camera{320, 256, 58.0};
  CandidateParams cp;
  const CandidateGrid g = make_candidates(scene.elements[0].center_of_mass, cp);
  ScoreParams sp;
  sp.min_distance_mm = 0;  // only occlusion matters here
  auto scores = score_candidates(all, camera, 0, g.candidates, cp.radius_mm, sp);
  add_visible_fractions(only, camera, 0, g.candidates, sp, scores);
  std::size_t hidden = 0;
  for (std::size_t i = 0; i < scores.size(); ++i) {
    const Eigen::Vector3d p = g.candidates[i].position;
    // The line from the candidate to the ball's centre crosses the plate well inside its edges: the whole
    // ball (within 50 mm of that line, less at the plate) is hidden.
    if (p.x() > 215) {
      const Eigen::Vector3d cross = p * (205.0 / p.x());
      if (std::abs(cross.y()) < 330 && std::abs(cross.z()) < 330) {
        EXPECT_EQ(scores[i].score_px, 0u) << "theta " << g.candidates[i].theta_deg << " phi " << g.candidates[i].phi_deg;
        EXPECT_EQ(scores[i].visible_fraction, 0.0);
        ++hidden;
      }
    }
    if (p.x() < 0) {
      EXPECT_GT(scores[i].score_px, 0u);
    }
  }
  EXPECT_GT(hidden, 50u);
  // The best views are on the free side of the plate and see the whole ball; the plate's side scores less.
  std::vector<std::size_t> order(scores.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return scores[a].score_px > scores[b].score_px; });
  for (int k = 0; k < 5; ++k) {
    EXPECT_LT(g.candidates[order[k]].position.x(), 200.0);
    EXPECT_DOUBLE_EQ(scores[order[k]].visible_fraction, 1.0);
  }
  double free_sum = 0, plate_sum = 0, free_n = 0, plate_n = 0;
  for (std::size_t i = 0; i < scores.size(); ++i) {
    const bool free_side = g.candidates[i].position.x() < -1;
    (free_side ? free_sum : plate_sum) += double(scores[i].score_px);
    (free_side ? free_n : plate_n) += 1;
  }
  EXPECT_GT(free_sum / free_n, 1.15 * plate_sum / plate_n);
}

TEST(Score, CandidatesInsideOrTooCloseToGeometryAreRejected) {
  Scene scene;
  add_mesh(scene, "ball", make_sphere(Eigen::Vector3d::Zero(), 50.0, 48, 24));
  // A closed box around the north pole of the candidate sphere (radius 600).
  add_mesh(scene, "housing", make_box(Eigen::Vector3d(-300, -300, 450), Eigen::Vector3d(300, 300, 800)));
  const Raycaster all(scene);
  const Camera camera{160, 128, 58.0};
  const CandidateGrid g = make_candidates(Eigen::Vector3d::Zero(), CandidateParams{});
  ScoreParams sp;
  sp.min_distance_mm = 0;
  const auto scores = score_candidates(all, camera, 0, g.candidates, 600.0, sp);
  for (std::size_t i = 0; i < scores.size(); ++i) {
    const Eigen::Vector3d p = g.candidates[i].position;
    const bool inside = p.z() > 451 && std::abs(p.x()) < 299 && std::abs(p.y()) < 299;
    const bool outside = p.z() < 449 || std::abs(p.x()) > 301 || std::abs(p.y()) > 301;
    if (inside) {
      EXPECT_TRUE(scores[i].rejected) << i;
      EXPECT_EQ(scores[i].reject_reason, "inside geometry");
      EXPECT_EQ(scores[i].score_px, 0u);
    }
    if (outside) {
      EXPECT_FALSE(scores[i].rejected) << i;
    }
  }
  // With a clearance of 100 mm, candidates near the housing's walls go too.
  sp.min_distance_mm = 100;
  const auto near = score_candidates(all, camera, 0, g.candidates, 600.0, sp);
  for (std::size_t i = 0; i < near.size(); ++i) {
    const Eigen::Vector3d p = g.candidates[i].position;
    if (p.z() > 360 && p.z() < 440 && std::abs(p.x()) < 290 && std::abs(p.y()) < 290) {
      EXPECT_TRUE(near[i].rejected);
    }
    if (p.z() < 340) {
      EXPECT_FALSE(near[i].rejected);
    }
  }
}

TEST(Score, MeasurablePixelsAreAStrictSubsetOfVisiblePixels) {
  Scene scene;
  add_mesh(scene, "ball", make_sphere(Eigen::Vector3d::Zero(), 50.0, 180, 90));
  const Raycaster all(scene);
  const Camera camera{640, 512, 58.0};
  const Pose pose = candidate_pose(Eigen::Vector3d(0, -400, 0), Eigen::Vector3d::Zero());
  const std::uint64_t seen = count_element_pixels(all, camera, pose, 0);
  MeasurableModel model;
  const std::uint64_t measurable = count_measurable_pixels(all, camera, pose, 0, model);
  // Camera incidence below 75 deg keeps about sin^2(75) = 93% of the disc; the projector 100 mm aside
  // removes another rim on its far side.
  EXPECT_LT(measurable, seen);
  EXPECT_GT(double(measurable), 0.80 * double(seen));
  EXPECT_LT(double(measurable), 0.95 * double(seen));
  model.max_incidence_deg = 89.9;
  model.baseline_mm = 1e-3;
  const std::uint64_t almost_all = count_measurable_pixels(all, camera, pose, 0, model);
  EXPECT_GT(double(almost_all), 0.99 * double(seen));
}

TEST(Score, ProjectedWindowContainsTheElement) {
  Scene scene;
  add_mesh(scene, "box", make_box(Eigen::Vector3d(-10, -20, -30), Eigen::Vector3d(10, 20, 30)));
  const Camera camera{640, 480, 58.0};
  const Pose pose = candidate_pose(Eigen::Vector3d(300, 0, 0), Eigen::Vector3d::Zero());
  const Raycaster all(scene);
  const PixelWindow w = projected_window(camera, pose, scene.elements[0]);
  const Render r = render(all, camera, pose);
  std::size_t inside = 0, total = 0;
  for (int row = 0; row < r.height_px; ++row)
    for (int col = 0; col < r.width_px; ++col)
      if (r.element[std::size_t(row) * r.width_px + col] == 0) {
        ++total;
        inside += (col >= w.col0 && col < w.col1 && row >= w.row0 && row < w.row1) ? 1 : 0;
      }
  EXPECT_GT(total, 0u);
  EXPECT_EQ(inside, total);
  // Behind the camera: empty window.
  const Pose away = candidate_pose(Eigen::Vector3d(300, 0, 0), Eigen::Vector3d(600, 0, 0));
  const PixelWindow e = projected_window(camera, away, scene.elements[0]);
  EXPECT_TRUE(e.col0 >= e.col1 || e.row0 >= e.row1 || (e.col0 == 0 && e.col1 == camera.width_px));
}

}  // namespace
}  // namespace ewis

namespace ewis {
namespace {

TEST(Score, FootprintCountEqualsTheRayCastersCountInAClutteredScene) {
  Scene scene;
  add_mesh(scene, "cable", make_tube({{-150, 0, 0}, {-50, 20, 10}, {50, -10, 30}, {150, 0, 0}}, 5.0, 16));
  add_mesh(scene, "pipe", make_cylinder({0, -100, -60}, {0, 100, 60}, 12.0, 32));
  add_mesh(scene, "bracket", make_box(Eigen::Vector3d(-60, -30, -40), Eigen::Vector3d(-40, 30, 40)));
  add_mesh(scene, "ring", make_torus({40, 0, 0}, {1, 0, 0}, 40, 4));
  const Raycaster all(scene);
  const Camera camera{480, 384, 58.0};
  CandidateParams cp;
  cp.step_deg = 20;
  cp.radius_mm = 350;
  const CandidateGrid g = make_candidates(scene.elements[0].center_of_mass, cp);
  std::uint64_t total = 0;
  for (const Candidate& c : g.candidates)
    for (std::uint32_t e = 0; e < 4; ++e) {
      const std::uint64_t fast = count_visible_pixels(all, camera, c.camera_to_cad, e);
      const std::uint64_t ref = count_element_pixels(all, camera, c.camera_to_cad, e);
      // The two paths build each pixel's ray direction in a different float order (the renderer fills Embree
      // packets straight from pixel coordinates), so a ray grazing a shared triangle edge can go either way:
      // allow one such pixel per 5000, nothing more.
      const double allowed = 1.0 + double(ref) / 5000.0;
      EXPECT_LE(std::abs(double(fast) - double(ref)), allowed)
          << "element " << e << " theta " << c.theta_deg << " phi " << c.phi_deg;
      total += ref;
    }
  EXPECT_GT(total, 10000u);
}

}  // namespace
}  // namespace ewis
