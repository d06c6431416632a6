#pragma once
// Circle fits used by the bend-radius measures (paper 4.3.1): an algebraic (Kasa) fit refined by a geometric
// Gauss-Newton fit in 2D, the same in 3D inside the best plane (PCA), and a seeded RANSAC circle in 2D.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace ewis {

struct Circle2d {
  bool ok = false;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double radius_mm = 0.0;
  double rms_mm = 0.0;  // RMS of |p - c| - r
  double radius_se_mm = 0.0;  // standard error of the radius (Gauss-Newton covariance, independent points)
};

struct Circle3d {
  bool ok = false;
  // A straight line fits at least as well as any circle (collinear points): radius_mm is infinity, `center`
  // is a point of the line and `direction` its direction.
  bool straight = false;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // of the best plane
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // the line's (straight) or the major PCA axis
  double radius_mm = 0.0;
  double rms_mm = 0.0;  // RMS distance to the circle in 3D (in-plane and out-of-plane parts)
  double radius_se_mm = 0.0;  // standard error of the radius (infinity when straight)
};

// Distance from p to the fitted circle (or line) in 3D; `radial`, when given, receives the signed in-plane
// part (positive outside the circle; the in-plane distance to the line when straight).
double circle_distance(const Circle3d& c, const Eigen::Vector3d& p, double* radial = nullptr);

// Least-squares circle: Kasa's algebraic fit, then Gauss-Newton on the geometric distances (kept only when
// it lowers the cost). ok is false for fewer than 3 points or collinear/degenerate data.
Circle2d fit_circle_2d(const std::vector<Eigen::Vector2d>& points);

// Circle in 3D: the plane through the centroid with the normal of least variance (PCA), then fit_circle_2d
// of the projections. rms_mm includes the distance off the plane, so a helix stretch that is no longer a
// circle shows in it.
Circle3d fit_circle_3d(const Eigen::Vector3d* points, std::size_t count);
inline Circle3d fit_circle_3d(const std::vector<Eigen::Vector3d>& points) {
  return fit_circle_3d(points.data(), points.size());
}

struct RansacCircleParams {
  double inlier_mm = 0.5;        // a point within this of the circle is an inlier
  int iterations = 500;          // hypotheses (3-point circles)
  double min_radius_mm = 0.0;    // hypotheses outside [min, max] are skipped
  double max_radius_mm = 1e9;
  std::uint64_t seed = 1;
};

struct RansacCircleResult {
  Circle2d circle;                       // least-squares refit on the inliers
  std::vector<std::uint32_t> inliers;    // indices into the input, increasing
};

// Deterministic for a seed.
RansacCircleResult ransac_circle_2d(const std::vector<Eigen::Vector2d>& points, const RansacCircleParams& params);

}  // namespace ewis
