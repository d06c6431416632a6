// Renders against analytic projections; count_element_pixels against the full render.
#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <cmath>

#include "ewis/raycast/raycaster.hpp"
#include "ewis/scene/primitives.hpp"

namespace {

using Eigen::Vector3d;

std::size_t count(const ewis::Render& r, std::uint32_t e) {
  std::size_t n = 0;
  for (std::uint32_t x : r.element) n += x == e;
  return n;
}

TEST(Render, SphereCoversAnalyticPixelArea) {
  // A sphere of radius r at distance d projects to an ellipse; on the optical axis a disc of area
  // pi f^2 r^2 / (d^2 - r^2).
  const double r = 100, d = 600;
  ewis::Scene s;
  const ewis::Mesh sphere = ewis::make_sphere(Vector3d(0, 0, 0), r, 256, 128);
  ewis::add_element(s, "sphere", sphere.vertices, sphere.triangles);
  const ewis::Raycaster rc(s);
  ewis::Camera cam;  // 58 deg
  cam.width_px = 640;
  cam.height_px = 512;
  const ewis::Pose pose = ewis::look_at(Vector3d(0, -d, 0), Vector3d(0, 0, 0));
  const ewis::Render img = ewis::render(rc, cam, pose);
  ASSERT_EQ(img.width_px, 640);
  ASSERT_EQ(img.distance_mm.size(), 640u * 512u);
  const double f = cam.focal_px();
  const double expected = M_PI * f * f * r * r / (d * d - r * r);
  EXPECT_NEAR(double(count(img, 0)), expected, 0.01 * expected);
  // Centre pixel distance ~ d - r; its normal points back at the camera.
  const std::size_t c = 256 * 640 + 320;
  EXPECT_NEAR(img.distance_mm[c], d - r, 0.1);
  EXPECT_GT(img.normal[c].dot(Eigen::Vector3f(0, -1, 0)), 0.999f);
  EXPECT_TRUE(std::isinf(img.distance_mm[0]));
  EXPECT_EQ(img.element[0], ewis::kNoElement);
  // The image is upright: a point above the centre (world +z, up hint) appears in a lower row index.
  double u, v;
  cam.project(pose.inverse() * Vector3d(0, 0, 50), u, v);
  EXPECT_LT(v, 256);
}

ewis::Scene cluttered() {
  ewis::Scene s;
  const ewis::Mesh plate = ewis::make_box(Vector3d(-300, -300, -20), Vector3d(300, 300, 0));
  ewis::add_element(s, "plate", plate.vertices, plate.triangles);
  for (int i = 0; i < 6; ++i) {
    std::vector<Vector3d> line;
    for (int k = 0; k <= 40; ++k)
      line.emplace_back(-200 + 400.0 * k / 40, -150 + 60.0 * i + 20 * std::sin(k * 0.3 + i), 15 + 10 * (i % 3));
    const ewis::Mesh tube = ewis::make_tube(line, 6, 24);
    ewis::add_element(s, "cable_" + std::to_string(i), tube.vertices, tube.triangles);
  }
  const ewis::Mesh clamp = ewis::make_box(Vector3d(-20, -200, 0), Vector3d(20, 200, 60));
  ewis::add_element(s, "bar", clamp.vertices, clamp.triangles);
  return s;
}

TEST(Render, CountElementPixelsEqualsFullRender) {
  const ewis::Scene s = cluttered();
  const ewis::Raycaster rc(s);
  ewis::Camera cam;
  cam.width_px = 320;
  cam.height_px = 256;
  const std::vector<ewis::Pose> poses = {ewis::look_at(Vector3d(100, -500, 400), Vector3d(0, 0, 0)),
                                         ewis::look_at(Vector3d(0, 0, 700), Vector3d(10, 0, 0)),
                                         ewis::look_at(Vector3d(-150, 0, 40), Vector3d(0, 0, 20))};  // inside the scene
  for (const ewis::Pose& pose : poses) {
    const ewis::Render img = ewis::render(rc, cam, pose);
    for (std::uint32_t e = 0; e < s.elements.size(); ++e)
      EXPECT_EQ(ewis::count_element_pixels(rc, cam, pose, e), count(img, e)) << "element " << e;
  }
  EXPECT_EQ(ewis::count_element_pixels(rc, cam, poses[0], 999), 0u);
  // Looking away from everything.
  EXPECT_EQ(ewis::count_element_pixels(rc, cam, ewis::look_at(Vector3d(0, 0, 500), Vector3d(0, 0, 1000)), 0), 0u);
}

TEST(Render, WindowMatchesFullRenderInside) {
  const ewis::Scene s = cluttered();
  const ewis::Raycaster rc(s);
  ewis::Camera cam;
  cam.width_px = 320;
  cam.height_px = 256;
  const ewis::Pose pose = ewis::look_at(Vector3d(100, -500, 400), Vector3d(0, 0, 0));
  const ewis::Render full = ewis::render(rc, cam, pose);
  const ewis::PixelWindow w{37, 21, 201, 150};
  const ewis::Render part = ewis::render(rc, cam, pose, &w);
  for (int row = 0; row < 256; ++row)
    for (int col = 0; col < 320; ++col) {
      const std::size_t i = std::size_t(row) * 320 + col;
      const bool in = col >= w.col0 && col < w.col1 && row >= w.row0 && row < w.row1;
      ASSERT_EQ(part.element[i], in ? full.element[i] : ewis::kNoElement);
      if (in) {
        ASSERT_EQ(part.distance_mm[i], full.distance_mm[i]);
      }
    }
}

TEST(Render, IncludeMaskAndPacketWidthsAgree) {
  const ewis::Scene s = cluttered();
  ewis::Camera cam;
  cam.width_px = 320;
  cam.height_px = 256;
  const ewis::Pose pose = ewis::look_at(Vector3d(100, -500, 400), Vector3d(0, 0, 0));
  const ewis::Raycaster all(s, {}, 1);
  const ewis::Render ref = ewis::render(all, cam, pose);
  for (int width : {4, 8, 16}) {
    const ewis::Raycaster rc(s, {}, width);
    const ewis::Render img = ewis::render(rc, cam, pose);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < img.element.size(); ++i) differ += img.element[i] != ref.element[i];
    EXPECT_LE(differ, 2u) << "width " << width;  // only rays grazing an edge may differ
  }
  // Without the plate, pixels that showed the plate show nothing or what lay under... nothing lies under it.
  std::vector<bool> mask(s.elements.size(), true);
  mask[0] = false;
  const ewis::Raycaster no_plate(s, mask);
  const ewis::Render img = ewis::render(no_plate, cam, pose);
  EXPECT_EQ(count(img, 0), 0u);
  EXPECT_EQ(ewis::count_element_pixels(no_plate, cam, pose, 0), 0u);
  for (std::uint32_t e = 1; e < s.elements.size(); ++e) EXPECT_GE(count(img, e), count(ref, e));
}

TEST(Render, SameImageForAnyThreadCount) {
  const ewis::Scene s = cluttered();
  ewis::Camera cam;
  cam.width_px = 320;
  cam.height_px = 256;
  const ewis::Pose pose = ewis::look_at(Vector3d(100, -500, 400), Vector3d(0, 0, 0));
  const ewis::Raycaster rc(s);
  const ewis::Render a = ewis::render(rc, cam, pose);
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const ewis::Raycaster rc1(s);  // BVH built on one thread
  const ewis::Render b = ewis::render(rc1, cam, pose);
  ASSERT_EQ(a.element, b.element);
  ASSERT_EQ(a.distance_mm, b.distance_mm);
}

}  // namespace
