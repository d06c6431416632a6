#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "ewis/core/cylinder.hpp"
#include "ewis/inspect/surface_clumps.hpp"
#include "paths.hpp"

using namespace ewis;

namespace {

const Eigen::Vector3d kSensor(0, 0, 600);  // tube_surface's sensor

// Moves the points within `half_mm` of `centre` in x and y (a square patch of the sensor's image, seen from above)
// along their rays by `offset_mm` (positive: away from the sensor), as a stereo mismatch does; their indices.
std::vector<std::uint32_t> move_patch(std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& centre, double half_mm,
                                      double offset_mm) {
  std::vector<std::uint32_t> moved;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (std::abs(pts[i].x() - centre.x()) > half_mm || std::abs(pts[i].y() - centre.y()) > half_mm) continue;
    if (pts[i].z() < centre.z() - 1.0) continue;  // the seen side only
    pts[i] += offset_mm * (pts[i] - kSensor).normalized();
    moved.push_back(std::uint32_t(i));
  }
  return moved;
}

// A polyline through every `every`-th sample of `axis` (and its last): a chain that cuts a bend's corner.
std::vector<Eigen::Vector3d> chord_polyline(const std::vector<Eigen::Vector3d>& axis, std::size_t every) {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < axis.size(); i += every) out.push_back(axis[i]);
  if ((axis.size() - 1) % every != 0) out.push_back(axis.back());
  return out;
}

// The largest distance of `pts` from the polyline less r: how far the surface stands off it.
double largest_offset(const std::vector<Eigen::Vector3d>& pts, const std::vector<Eigen::Vector3d>& line, double r) {
  double worst = 0.0;
  for (const Eigen::Vector3d& p : pts) {
    double d = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i + 1 < line.size(); ++i)
      d = std::min(d, distance_to_segment(Cylinder{line[i], line[i + 1], 0.0}, p));
    worst = std::max(worst, d - r);
  }
  return worst;
}

}  // namespace

// A 3.7 mm cable with a patch of about 5 x 5 pixels moved 1.4 mm along the rays (into the tube) and one moved 1 mm
// towards the sensor: both patches are found, point for point, and nothing else on the cable.
TEST(SurfaceClumps, APatchMovedAlongItsRaysIsFoundAndNothingElse) {
  const double r = 1.85;
  test::Turtle t;
  t.step = 0.5;
  t.straight(60.0);
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    std::vector<Eigen::Vector3d> pts = test::tube_surface(t.points, r, 0.1, seed);
    std::vector<std::uint32_t> patch = move_patch(pts, Eigen::Vector3d(20.0, 0.0, r), 1.2, 1.4);
    const std::vector<std::uint32_t> front = move_patch(pts, Eigen::Vector3d(40.0, 0.6, r), 1.2, -1.0);
    ASSERT_GE(patch.size(), 9u);
    ASSERT_GE(front.size(), 9u);
    patch.insert(patch.end(), front.begin(), front.end());
    std::sort(patch.begin(), patch.end());
    const SurfaceClumps c = surface_step_clumps(pts, t.points, r, kSensor, 0.5);
    EXPECT_EQ(c.clumps, 2u) << "seed " << seed;
    EXPECT_EQ(c.points, patch) << "seed " << seed;
    // across the surface the ray noise shows as less (sigma x cos(incidence))
    EXPECT_GT(c.sigma_mm, 0.04) << "seed " << seed;
    EXPECT_LT(c.sigma_mm, 0.1) << "seed " << seed;
  }
}

// A tight bend (R = 2 d, 90 deg) whose centreline is a chain of 8 mm chords: the surface at the apex lies off that
// centreline by up to 1 mm, a trend over the whole arc with no step at any edge, and is kept whole. On a chain of
// one-radius steps (as the trace's) a patch at the apex is found.
TEST(SurfaceClumps, ATightBendsApexIsNoClumpAPatchThereIs) {
  const double d = 3.7, r = 0.5 * d;
  test::Turtle t;
  t.step = 0.5;
  t.straight(30.0);
  t.arc(2.0 * d, 90.0, Eigen::Vector3d::UnitY());
  t.straight(30.0);
  const std::vector<Eigen::Vector3d> coarse = chord_polyline(t.points, 16), chain = chord_polyline(t.points, 4);
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    std::vector<Eigen::Vector3d> pts = test::tube_surface(t.points, r, 0.1, seed);
    ASSERT_GT(largest_offset(pts, coarse, r), 0.8) << "seed " << seed;  // beyond the threshold (0.5 mm)
    EXPECT_TRUE(surface_step_clumps(pts, coarse, r, kSensor, 0.5).points.empty()) << "seed " << seed;
    EXPECT_TRUE(surface_step_clumps(pts, chain, r, kSensor, 0.5).points.empty()) << "seed " << seed;
    // the arc's middle, on its top
    const Eigen::Vector3d apex = Eigen::Vector3d(30.0, 2.0 * d, 0.0) +
                                 2.0 * d * Eigen::Vector3d(std::cos(M_PI / 4), -std::sin(M_PI / 4), 0.0);
    const std::vector<std::uint32_t> patch = move_patch(pts, apex + Eigen::Vector3d(0, 0, r), 1.0, 1.5);
    ASSERT_GE(patch.size(), 6u);
    const SurfaceClumps c = surface_step_clumps(pts, chain, r, kSensor, 0.5);
    EXPECT_EQ(c.points, patch) << "seed " << seed;
  }
}
