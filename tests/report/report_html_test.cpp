// report.html: self-contained, verdict, every cable, inline PNG pictures of the right size, no web links.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "ewis/core/error.hpp"
#include "ewis/io/cloud_io.hpp"
#include "ewis/report/pictures.hpp"
#include "ewis/report/report_html.hpp"
#include "report_fixture.hpp"

namespace ewis {
namespace {

std::vector<std::uint8_t> base64_decode(const std::string& s) {
  auto val = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::vector<std::uint8_t> out;
  std::uint32_t acc = 0;
  int bits = 0;
  for (char c : s) {
    const int v = val(c);
    if (v < 0) continue;
    acc = (acc << 6) | std::uint32_t(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(std::uint8_t((acc >> bits) & 0xff));
    }
  }
  return out;
}

struct PngSize {
  bool ok = false;
  std::uint32_t width = 0, height = 0;
};
PngSize png_size(const std::vector<std::uint8_t>& b) {
  static const std::uint8_t sig[8] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
  PngSize s;
  if (b.size() < 24 || !std::equal(sig, sig + 8, b.begin())) return s;
  if (std::string(b.begin() + 12, b.begin() + 16) != "IHDR") return s;
  auto be32 = [&](std::size_t o) { return (std::uint32_t(b[o]) << 24) | (std::uint32_t(b[o + 1]) << 16) | (std::uint32_t(b[o + 2]) << 8) | b[o + 3]; };
  s.ok = true;
  s.width = be32(16);
  s.height = be32(20);
  return s;
}

std::vector<std::string> embedded_pngs(const std::string& html) {
  std::vector<std::string> out;
  const std::string key = "data:image/png;base64,";
  for (std::size_t p = html.find(key); p != std::string::npos; p = html.find(key, p + 1)) {
    const std::size_t b = p + key.size(), e = html.find('"', b);
    out.push_back(html.substr(b, e - b));
  }
  return out;
}

TEST(ReportHtml, FailingInspectionShowsVerdictCablesAndPictures) {
  const test::ReportFixture f = test::make_fixture(true);
  ReportParams params;
  const std::string html = report_html(f.result, f.scene, f.plan, params);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(html.find("</html>"), std::string::npos);
  EXPECT_NE(html.find("vfail\">FAIL"), std::string::npos);
  EXPECT_EQ(html.find("verdict vpass"), std::string::npos);
  EXPECT_NE(html.find("cable_A"), std::string::npos);
  EXPECT_NE(html.find("cable_B"), std::string::npos);
  EXPECT_NE(html.find("pipe_1"), std::string::npos);
  EXPECT_NE(html.find("foreign object"), std::string::npos);
  // Numbers with units: the bend radius against the rule, the gap against the clearance.
  EXPECT_NE(html.find("30.4 mm"), std::string::npos);
  EXPECT_NE(html.find("48.0 mm"), std::string::npos);
  EXPECT_NE(html.find("1.20 mm"), std::string::npos);
  // Self-contained: no links to anything outside the file.
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(std::regex_search(html, std::regex("src=\"(?!data:)")), false);

  // Pictures: the scan (sensor aspect) plus two close-ups (points, CAD) per defect: 1 bend + 2 interferences.
  const std::vector<std::string> pngs = embedded_pngs(html);
  ASSERT_EQ(pngs.size(), 1u + 2u * 3u);
  const PngSize main = png_size(base64_decode(pngs[0]));
  ASSERT_TRUE(main.ok);
  EXPECT_EQ(main.width, 1024u);
  EXPECT_EQ(main.height, 819u);  // 1024 x 512 / 640, rounded
  for (std::size_t i = 1; i < pngs.size(); ++i) {
    const PngSize c = png_size(base64_decode(pngs[i]));
    ASSERT_TRUE(c.ok) << i;
    EXPECT_EQ(c.width, std::uint32_t(params.closeup_width_px));
    EXPECT_EQ(c.height, std::uint32_t(params.closeup_height_px));
  }
}

TEST(ReportHtml, PassingInspectionHasOnlyTheScanPicture) {
  const test::ReportFixture f = test::make_fixture(false);
  const std::string html = report_html(f.result, f.scene, f.plan);
  EXPECT_NE(html.find("vpass\">PASS"), std::string::npos);
  EXPECT_EQ(html.find("class=\"fail\""), std::string::npos);
  EXPECT_EQ(embedded_pngs(html).size(), 1u);
  EXPECT_NE(html.find("No bend-radius or clearance defect"), std::string::npos);
}

TEST(ReportHtml, CableNotFoundFailsItsRow) {
  test::ReportFixture f = test::make_fixture(false);
  f.result.cables[1].found = false;
  f.result.cables[1].bend_ok.reset();
  f.result.cables[1].clearance_ok.reset();
  f.result.pass = false;
  const std::string html = report_html(f.result, f.scene, f.plan);
  EXPECT_NE(html.find("vfail\">FAIL"), std::string::npos);
  EXPECT_NE(html.find("<td>cable found in the scan</td><td>no</td>"), std::string::npos);
}

TEST(ReportHtml, NamesAreEscaped) {
  test::ReportFixture f = test::make_fixture(true);
  f.result.cables[0].name = "cable<&>\"x\"";
  const std::string html = report_html(f.result, f.scene, f.plan);
  EXPECT_EQ(html.find("cable<&>"), std::string::npos);
  EXPECT_NE(html.find("cable&lt;&amp;&gt;&quot;x&quot;"), std::string::npos);
  EXPECT_EQ(html_escape("a'b"), "a&#39;b");
}

TEST(ReportFiles, WritesHtmlAndColouredClouds) {
  const test::ReportFixture f = test::make_fixture(true);
  const std::string dir = test::test_dir("files");
  ReportFiles files;
  files.clouds = true;
  files.json = true;
  write_report_files(f.result, f.scene, f.plan, dir + "/out", files);
  for (const char* name : {"report.html", "report.json", "cables.ply", "interferences.ply", "rest.ply"})
    EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/out/" + name)) << name;
  const CloudFile cables = read_cloud(dir + "/out/cables.ply");
  const CloudFile inter = read_cloud(dir + "/out/interferences.ply");
  const CloudFile rest = read_cloud(dir + "/out/rest.ply");
  EXPECT_EQ(cables.cloud.size(), f.result.cables[0].trace.points.size() + f.result.cables[1].trace.points.size());
  EXPECT_GT(inter.cloud.size(), 0u);
  EXPECT_EQ(cables.cloud.size() + inter.cloud.size() + rest.cloud.size(), f.result.cloud.size());
  EXPECT_TRUE(cables.cloud.has_colors());
  // No temporary files left behind.
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir + "/out")) ++n;
  EXPECT_EQ(n, 5u);
}

TEST(ReportFiles, RefusesAFileAsFolder) {
  const test::ReportFixture f = test::make_fixture(false);
  const std::string dir = test::test_dir("notdir");
  std::ofstream(dir + "/file") << "x";
  EXPECT_THROW(write_report_files(f.result, f.scene, f.plan, dir + "/file"), InputError);
}

}  // namespace
}  // namespace ewis
