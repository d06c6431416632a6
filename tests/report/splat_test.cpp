// The depth-tested splat of the report's pictures (src/report/draw.hpp) against a brute-force reference: each
// pixel holds the nearest point whose disc covers it, the lowest index among equally near ones, for any number
// of threads (the points are splatted in parallel blocks with an atomic minimum).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "draw.hpp"

using namespace ewis;
using namespace ewis::report_detail;

namespace {

// One pixel's answer the slow way: every point, its disc, the nearest and then the lowest index.
std::uint64_t reference_pixel(const std::vector<Eigen::Vector3f>& pts, const Camera& cam, int x, int y, int r) {
  std::uint64_t best = SplatBuffer::kEmpty;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Eigen::Vector3d p = pts[i].cast<double>();  // camera at the origin, looking along +z
    double u, v;
    if (p.z() <= 1e-3 || !cam.project(p, u, v)) continue;
    const int dx = x - static_cast<int>(std::floor(u)), dy = y - static_cast<int>(std::floor(v));
    if (std::abs(dx) > r || std::abs(dy) > r || dx * dx + dy * dy > r * r + r) continue;
    best = std::min(best, SplatBuffer::pack(static_cast<float>(p.z()), static_cast<std::uint32_t>(i)));
  }
  return best;
}

}  // namespace

TEST(Splat, EachPixelHoldsTheNearestPointAndTheLowestIndexOnATie) {
  Camera cam;
  cam.width_px = 32, cam.height_px = 24, cam.hfov_deg = 40.0;
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> lateral(-190.0f, 190.0f), depth(500.0f, 520.0f);
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < 8000; ++i) {
    // Depths on a 1 mm grid: many points equally near at one pixel, so the tie rule decides.
    const float z = std::round(depth(rng));
    pts.emplace_back(lateral(rng) * z / 500.0f, lateral(rng) * 0.75f * z / 500.0f, z);
  }
  pts.emplace_back(0.0f, 0.0f, -5.0f);  // behind the camera: nowhere
  for (int r : {0, 1, 2}) {
    SplatBuffer first;
    for (int threads : {1, 2, 4}) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
      const SplatBuffer buf = splat_points(pts, {}, cam, Pose::Identity(), r);
      ASSERT_EQ(buf.size(), std::size_t(cam.width_px * cam.height_px));
      if (threads == 1) {
        first = buf;
        std::size_t covered = 0;
        for (int y = 0; y < cam.height_px; ++y)
          for (int x = 0; x < cam.width_px; ++x) {
            const std::size_t k = std::size_t(y) * cam.width_px + x;
            ASSERT_EQ(buf.key[k], reference_pixel(pts, cam, x, y, r)) << "pixel " << x << "," << y << " r " << r;
            if (buf.point(k) < 0) continue;
            ++covered;
            EXPECT_EQ(buf.depth_mm(k), pts[std::size_t(buf.point(k))].z());
          }
        EXPECT_GT(covered, buf.size() * 9 / 10) << "r " << r;  // ~10 points a pixel across the frame
      } else {
        EXPECT_EQ(buf.key, first.key) << threads << " threads, r " << r;
      }
    }
  }
  // Points left out by `keep` are nowhere; an empty pixel reads as no point at infinite depth.
  const std::vector<std::uint8_t> none(pts.size(), 0);
  const SplatBuffer empty = splat_points(pts, none, cam, Pose::Identity(), 1);
  EXPECT_EQ(empty.point(0), -1);
  EXPECT_TRUE(std::isinf(empty.depth_mm(0)));
  EXPECT_TRUE(std::all_of(empty.key.begin(), empty.key.end(), [](std::uint64_t w) { return w == SplatBuffer::kEmpty; }));
}

// The picture's grey scale runs between the 2nd and 98th percentiles of the covered pixels' depths: exactly the
// values a full sort puts at those ranks, however many pixels share a depth or how wide the depths spread.
TEST(Splat, DepthRangeIsTheCoveredPixelsPercentiles) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 6; ++trial) {
    SplatBuffer buf;
    buf.width_px = 97, buf.height_px = 61;
    buf.key.assign(std::size_t(buf.width_px) * buf.height_px, SplatBuffer::kEmpty);
    // trials 0-2: depths over 300-900 mm; 3-4: many equal depths; 5: 1e-3 to 1e6 mm
    std::uniform_real_distribution<double> wide(300.0, 900.0), huge(-3.0, 6.0);
    std::uniform_int_distribution<int> few(0, 4), cover(0, 3);
    std::vector<float> depths;
    for (std::size_t k = 0; k < buf.key.size(); ++k) {
      if (cover(rng) == 0) continue;  // a quarter of the pixels empty
      const float z = trial < 3 ? float(wide(rng)) : trial < 5 ? float(500 + few(rng)) : float(std::pow(10.0, huge(rng)));
      buf.key[k] = SplatBuffer::pack(z, std::uint32_t(k));
      depths.push_back(z);
    }
    std::sort(depths.begin(), depths.end());
    const std::size_t n = depths.size();
    double near_mm = 0, far_mm = 0;
    ASSERT_TRUE(depth_range(buf, near_mm, far_mm));
    EXPECT_EQ(near_mm, depths[n / 50]) << "trial " << trial;
    const double far_expected = depths[n - 1 - n / 50] > depths[n / 50] ? depths[n - 1 - n / 50] : depths[n / 50] + 1.0;
    EXPECT_EQ(far_mm, far_expected) << "trial " << trial;
  }
  SplatBuffer empty;
  empty.width_px = 4, empty.height_px = 4;
  empty.key.assign(16, SplatBuffer::kEmpty);
  double a = 0, b = 0;
  EXPECT_FALSE(depth_range(empty, a, b));
}
