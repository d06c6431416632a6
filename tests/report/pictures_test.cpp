// The report's pictures: labels, the sensor-view splat and the close-ups show what they claim.
#include <gtest/gtest.h>

#include "ewis/report/pictures.hpp"
#include "report_fixture.hpp"

namespace ewis {
namespace {

std::size_t count_color(const Image& img, const Rgb& c, int tolerance = 0) {
  std::size_t n = 0;
  for (std::size_t i = 0; i + 2 < img.rgb.size(); i += 3)
    if (std::abs(img.rgb[i] - c[0]) <= tolerance && std::abs(img.rgb[i + 1] - c[1]) <= tolerance &&
        std::abs(img.rgb[i + 2] - c[2]) <= tolerance)
      ++n;
  return n;
}

// Pixels whose hue is that of c (any brightness): r:g:b ratios within a few per cent.
std::size_t count_hue(const Image& img, const Rgb& c) {
  std::size_t n = 0;
  const double cs = c[0] + c[1] + c[2];
  for (std::size_t i = 0; i + 2 < img.rgb.size(); i += 3) {
    const double s = img.rgb[i] + img.rgb[i + 1] + img.rgb[i + 2];
    if (s < 60) continue;
    bool same = true;
    for (int k = 0; k < 3; ++k) same = same && std::abs(img.rgb[i + k] / s - c[k] / cs) < 0.03;
    n += same;
  }
  return n;
}

TEST(PointLabels, CablesInterferencesAndRest) {
  const test::ReportFixture f = test::make_fixture(true);
  const PointLabels l = label_points(f.result);
  ASSERT_EQ(l.kind.size(), f.result.cloud.size());
  for (std::uint32_t i : f.result.cables[0].trace.points) EXPECT_EQ(l.kind[i], PointKind::Cable);
  for (std::uint32_t i : f.result.cables[1].interferences[1].points) {
    EXPECT_EQ(l.kind[i], PointKind::Interference);
    EXPECT_EQ(l.foreign[i], 1);
    EXPECT_EQ(l.cable[i], 1);
  }
  std::size_t rest = 0;
  for (PointKind k : l.kind) rest += k == PointKind::Rest;
  EXPECT_GT(rest, f.result.cloud.size() / 2);  // mostly the plate
}

TEST(Pictures, SensorViewShowsCablesInterferencesAndGreyRest) {
  const test::ReportFixture f = test::make_fixture(true);
  const PointLabels l = label_points(f.result);
  const Camera cam = report_camera(f.plan, 640);
  EXPECT_EQ(cam.height_px, 512);
  SplatParams p;
  p.eye_dome_shading = false;
  p.draw_chains = false;
  p.draw_markers = false;
  const Image img = splat_scan(f.result, l, cam, f.result.scan_to_cad, p);
  ASSERT_EQ(img.width_px, 640);
  // Every scan pixel is covered (the scan is a one-ray-per-pixel render of the same camera): only the
  // plate's border is background. Cable A in its colour, the foreign sphere red, the pipe cluster orange.
  EXPECT_GT(count_hue(img, cable_color(0)), f.result.cables[0].trace.points.size() / 2);
  EXPECT_GT(count_hue(img, cable_color(1)), f.result.cables[1].trace.points.size() / 2);
  EXPECT_GT(count_hue(img, interference_color(true)), f.result.cables[1].interferences[1].points.size() / 2);
  EXPECT_GT(count_hue(img, interference_color(false)), 10u);
  // The plate is grey (r == g == b), not white.
  std::size_t grey = 0;
  for (std::size_t i = 0; i < img.rgb.size(); i += 3)
    grey += img.rgb[i] == img.rgb[i + 1] && img.rgb[i + 1] == img.rgb[i + 2] && img.rgb[i] < 230 && img.rgb[i] > 60;
  EXPECT_GT(grey, f.result.cloud.size() / 2);

  // With chains and markers: white axis lines with black outlines and magenta bend rings appear.
  const Image full = splat_scan(f.result, l, cam, f.result.scan_to_cad);
  EXPECT_GT(count_color(full, {255, 255, 255}), 300u);
  EXPECT_GT(count_color(full, {255, 0, 255}), 50u);
}

TEST(Pictures, DefectViewsAndCloseups) {
  const test::ReportFixture f = test::make_fixture(true);
  const std::vector<DefectView> views = defect_views(f.result);
  ASSERT_EQ(views.size(), 3u);
  EXPECT_EQ(views[0].cable, 0);
  EXPECT_EQ(views[0].interference, -1);
  EXPECT_NE(views[0].title.find("30.4 mm < allowed 48.0 mm"), std::string::npos);
  EXPECT_EQ(views[1].interference, 0);
  EXPECT_NE(views[1].title.find("pipe_1"), std::string::npos);
  EXPECT_NE(views[2].title.find("foreign object"), std::string::npos);
  EXPECT_EQ(defect_views(f.result, 2).size(), 2u);

  const PointLabels l = label_points(f.result);
  const Raycaster caster(f.scene);
  for (const DefectView& v : views) {
    const CloseupCamera cam = closeup_camera(f.result, v, 320, 240);
    // The target projects to the image centre.
    const Eigen::Vector3d pc = cam.camera_to_cad.inverse() * v.target;
    double u, vv;
    ASSERT_TRUE(cam.camera.project(pc, u, vv));
    EXPECT_NEAR(u, 160.0, 1.0);
    EXPECT_NEAR(vv, 120.0, 1.0);
    // +-half_extent covers at least the smaller side.
    EXPECT_GE(std::tan(cam.camera.vfov_deg() * M_PI / 360.0) * pc.z(), v.half_extent_mm * 0.99);
    const Image s = closeup_splat(f.result, l, v, cam);
    const Image r = closeup_render(f.result, l, caster, v, cam);
    EXPECT_EQ(s.width_px, 320);
    EXPECT_EQ(r.height_px, 240);
    // The zoomed splat is closed: few white holes inside the plate (points grow with the zoom).
    std::size_t white = count_color(s, {255, 255, 255});
    EXPECT_LT(white, std::size_t(320 * 240 / 3));
    // The CAD render shows the cable in its colour (shaded).
    EXPECT_GT(count_hue(r, cable_color(std::size_t(v.cable))), 200u);
  }
}

}  // namespace
}  // namespace ewis
