// report.html opened by a real browser (Debian's headless Chromium), offline: the screenshot must show the
// pictures (the cables' colours of the scan picture) and the verdict badge. Skipped when Chromium is absent.
#include <gtest/gtest.h>
#include <stb/stb_image.h>

#include <cstdlib>
#include <filesystem>

#include "ewis/report/pictures.hpp"
#include "ewis/report/report_html.hpp"
#include "report_fixture.hpp"

namespace ewis {
namespace {

std::string find_chromium() {
  for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (std::filesystem::exists(p)) return p;
  return {};
}

std::size_t count_near(const unsigned char* px, int n, const Rgb& c, int tol) {
  std::size_t count = 0;
  for (int i = 0; i < n; ++i) {
    const unsigned char* p = px + std::size_t(i) * 3;
    count += std::abs(p[0] - c[0]) <= tol && std::abs(p[1] - c[1]) <= tol && std::abs(p[2] - c[2]) <= tol;
  }
  return count;
}

TEST(ReportChromium, ScreenshotShowsPicturesAndVerdict) {
  const std::string chromium = find_chromium();
  if (chromium.empty()) GTEST_SKIP() << "chromium is not installed (apt-get install chromium): browser check skipped";
  const test::ReportFixture f = test::make_fixture(true);
  const std::string dir = test::test_dir("chromium");
  write_report_files(f.result, f.scene, f.plan, dir);
  const std::string html = std::filesystem::absolute(dir + "/report.html").string();
  const std::string shot = dir + "/screenshot.png";
  // No network at all: the page must not need it (self-contained), and the test must not hang on it.
  const std::string cmd = "timeout 120 " + chromium +
                          " --headless --no-sandbox --disable-gpu --disable-background-networking "
                          "--hide-scrollbars --no-first-run --user-data-dir=" + dir + "/profile"
                          " --screenshot=" + shot + " --window-size=1280,2000 file://" + html + " > " + dir +
                          "/chromium.log 2>&1";
  const int rc = std::system(cmd.c_str());
  ASSERT_EQ(rc, 0) << "chromium failed, see " << dir << "/chromium.log";
  int w = 0, h = 0, ch = 0;
  unsigned char* px = stbi_load(shot.c_str(), &w, &h, &ch, 3);
  ASSERT_NE(px, nullptr) << "no screenshot at " << shot;
  EXPECT_EQ(w, 1280);
  EXPECT_EQ(h, 2000);
  // The scan picture: cable A's blue and cable B's green (shaded within a few levels on the top surface).
  const std::size_t blue = count_near(px, w * h, cable_color(0), 40);
  const std::size_t green = count_near(px, w * h, cable_color(1), 40);
  // The FAIL badge (#c62828) and the red pass/fail cells (#ffcdd2).
  const std::size_t badge = count_near(px, w * h, Rgb{198, 40, 40}, 8);
  const std::size_t fail_cells = count_near(px, w * h, Rgb{255, 205, 210}, 4);
  stbi_image_free(px);
  EXPECT_GT(blue, 2000u);
  EXPECT_GT(green, 1000u);
  EXPECT_GT(badge, 500u);
  EXPECT_GT(fail_cells, 500u);
}

}  // namespace
}  // namespace ewis
