#pragma once
// Least-squares cylinder fit of a sub-cable (paper 4.2.3, "refine by least squares"), made robust for real
// scans (DESIGN.md "Measurement lessons"): Gauss-Newton on the axis point, axis direction and radius,
// trimming residual outliers between rounds; optionally measuring residuals along the camera rays (the
// noise direction of a structured-light or stereo sensor) instead of perpendicular to the surface.
#include <Eigen/Core>
#include <vector>

namespace ewis {

struct CylinderFitParams {
  int rounds = 3;                  // trimming rounds (re-select inliers from the residuals)
  int iterations = 6;              // Gauss-Newton iterations per round
  double trim_sigmas = 2.5;        // inliers: |residual| <= trim_sigmas x robust sigma (MAD)
  double min_sigma_mm = 0.05;      // floor of the robust sigma (noise-free data)
  double max_radius_mm = 1e9;      // the fit fails when the radius leaves (0, max_radius_mm]
  bool fix_radius = false;         // keep the initial radius (fit the axis only)
  bool use_sensor = false;         // residuals along the ray from `sensor` to each point
  // > 0: the Gauss-Newton rounds run on an evenly strided subset of at most this many points (the final
  // inliers, rms and arc still use all points); the fit's cost no longer grows with the scan's density
  int max_points = 0;
  Eigen::Vector3d sensor = Eigen::Vector3d::Zero();
};

// A fit with fewer inliers than this (2 per 10 deg sector round the whole circle) is sparse: a thin tube in a
// sparse scan. Its seen arc is then measured as an angular range, and in the trace its radius is too loose for
// the plain radius-jump limit (tube_step.cpp).
constexpr int kSparseFitInliers = 72;

struct CylinderFitResult {
  bool ok = false;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // on the axis, the foot of the initial point
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   // unit, same hemisphere as the initial axis
  double radius_mm = 0.0;
  double rms_mm = 0.0;          // rms of the inliers' residuals (surface distance)
  int inliers = 0;
  double arc_deg = 0.0;         // angular extent of the inliers around the axis (360 = full circle)
  std::vector<char> inlier;     // per input point
};

// Fits a cylinder to `points` starting from an axis through `point` along `axis` with `radius_mm`.
CylinderFitResult fit_cylinder(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& point,
                               const Eigen::Vector3d& axis, double radius_mm, const CylinderFitParams& params = {});

// Least-squares circle in 2D (algebraic Kasa start, then geometric Gauss-Newton with trimming).
struct CircleFitResult {
  bool ok = false;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double radius_mm = 0.0;
  double rms_mm = 0.0;
  int inliers = 0;
};
CircleFitResult fit_circle(const std::vector<Eigen::Vector2d>& points, double trim_sigmas = 2.5,
                           double min_sigma_mm = 0.05);

}  // namespace ewis
