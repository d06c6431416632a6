#pragma once
// Analytic centrelines for the inspect tests: a turtle that lays straight runs and circular arcs.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "ewis/inspect/bend_radius.hpp"
#include "ewis/inspect/fillet_fit.hpp"

namespace ewis::test {

struct Turtle {
  Eigen::Vector3d pos = Eigen::Vector3d::Zero();
  Eigen::Vector3d dir = Eigen::Vector3d::UnitX();
  double step = 1.0;  // spacing of the points laid
  std::vector<Eigen::Vector3d> points{Eigen::Vector3d::Zero()};

  void straight(double len) {
    const int n = std::max(1, int(std::ceil(len / step)));
    const Eigen::Vector3d start = pos;
    for (int i = 1; i <= n; ++i) points.push_back(start + dir * (len * i / n));
    pos = start + dir * len;
  }
  // Arc of radius r turning by angle_deg toward `side` (a unit vector perpendicular to dir).
  void arc(double r, double angle_deg, const Eigen::Vector3d& side) {
    const Eigen::Vector3d axis = dir.cross(side).normalized();
    const Eigen::Vector3d center = pos + side * r;
    const Eigen::Vector3d rel = pos - center;
    const double angle = angle_deg * M_PI / 180.0;
    const int n = std::max(2, int(std::ceil(r * angle / step)));
    for (int i = 1; i <= n; ++i) {
      const Eigen::AngleAxisd rot(angle * i / n, axis);
      points.push_back(center + rot * rel);
    }
    const Eigen::AngleAxisd rot(angle, axis);
    pos = center + rot * rel;
    dir = (rot * dir).normalized();
  }
};

// Centreline of a line-helix-line bend: a straight leg of `leg_mm`, a helix of radius r and rise c per radian
// (axis along z; curvature radius (r^2 + c^2) / r) turning by angle_deg about its axis, a straight leg; points
// about `step` mm apart.
inline std::vector<Eigen::Vector3d> helical_bend(double r, double c, double angle_deg, double leg_mm, double step) {
  const double k = std::hypot(r, c), end = k * angle_deg * M_PI / 180.0;
  const auto at = [&](double s) { return Eigen::Vector3d(r * std::sin(s / k), r - r * std::cos(s / k), c * s / k); };
  const auto tangent = [&](double s) {
    return Eigen::Vector3d(r * std::cos(s / k), r * std::sin(s / k), c).normalized();
  };
  std::vector<Eigen::Vector3d> pts;
  for (double s = -leg_mm; s < 0; s += step) pts.push_back(at(0) + s * tangent(0));
  for (double s = 0; s < end; s += step) pts.push_back(at(s));
  for (double s = 0; s <= leg_mm; s += step) pts.push_back(at(end) + s * tangent(end));
  return pts;
}

inline std::vector<Eigen::Vector3d> add_noise(std::vector<Eigen::Vector3d> pts, double sigma, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, sigma);
  for (auto& p : pts) p += Eigen::Vector3d(n(rng), n(rng), n(rng));
  return pts;
}

// Upper-half surface points (sensor far above, +z) of a tube swept along a centreline, with Gaussian noise along the
// sensor's rays. The half is the one around the upward direction across the tube (+z for a centreline in the xy
// plane; a centreline that climbs, as a helix's does, has it tilted).
inline std::vector<Eigen::Vector3d> tube_surface(const std::vector<Eigen::Vector3d>& axis, double r, double noise_mm,
                                                 std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const Eigen::Vector3d sensor(0, 0, 600);
  const int around = std::max(8, int(std::ceil(M_PI * r / 0.5)));
  std::vector<Eigen::Vector3d> pts;
  for (std::size_t i = 0; i + 1 < axis.size(); ++i) {
    const Eigen::Vector3d t = (axis[i + 1] - axis[i]).normalized();
    const Eigen::Vector3d n1 = (Eigen::Vector3d::UnitZ() - t.z() * t).normalized(), n2 = t.cross(n1).normalized();
    for (int k = 0; k < around; ++k) {
      const double phi = -0.5 * M_PI + M_PI * (k + 0.5) / around;
      const Eigen::Vector3d q = axis[i] + r * (std::cos(phi) * n1 + std::sin(phi) * n2);
      pts.push_back(q + noise_mm * gauss(rng) * (q - sensor).normalized());
    }
  }
  return pts;
}

// The cable's minimum bend radius through the whole refinement: the circle windows on the centreline (noise
// `centreline_noise_mm` per axis), then the fits on the upper-half surface points of a tube of radius d / 2 with
// `noise_mm` along the rays.
inline double refined_min_radius(const std::vector<Eigen::Vector3d>& axis, double d, double noise_mm,
                                 std::uint32_t seed, std::uint32_t centreline_seed,
                                 const FilletRefineParams& params = {}, double centreline_noise_mm = 0.08) {
  const std::vector<Eigen::Vector3d> surface = tube_surface(axis, 0.5 * d, noise_mm, seed);
  const std::vector<Eigen::Vector3d> centreline = add_noise(axis, centreline_noise_mm, centreline_seed);
  BendRadiusResult b = measure_bend_radius(centreline, d);
  refine_bends_with_fillets(b, centreline, surface, 0.5 * d, d, params);
  EXPECT_TRUE(b.min_radius_mm) << "seed " << seed;
  return b.min_radius_mm.value_or(0.0);
}

}  // namespace ewis::test
