#pragma once
// Bend radius from the cable's SURFACE points with a smooth tube: the centreline a quartic curve over a chord
// (origin + t u + f(t) v + g(t) w, f and g quartics in t), swept by the tube radius. Why: a cable routed along a
// spline (a routing tool's, another simulator's) bends with a curvature that changes all the time; its minimum
// radius is where the curvature peaks, and a circle or a line-arc-line fillet over a window of a few diameters
// averages the peak away (bench/spline_scenes.py: every bend of 3-20 d read 3-37 % high). A quartic follows a
// curvature that rises and falls within the window, so its peak is measured, not averaged. On a line-arc-line
// bend the fillet is the right model and the quartic overshoots at the arc's ends; bend_refine chooses between
// the two by their robust costs on the same points (see FilletRefineParams::smooth_*).
#include <Eigen/Core>
#include <array>
#include <vector>

#include "ewis/filter/noise_correlation.hpp"

namespace ewis {

struct SmoothTubeModel {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // the chord's middle
  Eigen::Vector3d u = Eigen::Vector3d::UnitX();      // along the chord (unit)
  Eigen::Vector3d v = Eigen::Vector3d::UnitY();      // v, w: unit, perpendicular to u and each other
  Eigen::Vector3d w = Eigen::Vector3d::UnitZ();
  double half_chord_mm = 1.0;                        // the curve's parameter is tau = t / half_chord_mm in [-1, 1]
  std::array<double, 5> f{}, g{};                    // f(tau) = sum f[k] tau^k (mm), along v; g along w
  double tube_radius_mm = 1.0;

  Eigen::Vector3d point(double tau) const;
  double tau_of(const Eigen::Vector3d& p) const;    // p's projection on the chord, as a parameter
  bool over_chord(const Eigen::Vector3d& p) const;  // tau_of(p) within [-1, 1]: the points a fit uses
  // Curvature (1/mm) of the centreline at tau.
  double curvature(double tau) const;
};

// Distance from p to the model's centreline (closest point by Newton steps from p's projection on the chord;
// tau_io in: the start (nan: from the projection), out: the closest point's parameter).
double smooth_tube_centreline_distance(const SmoothTubeModel& m, const Eigen::Vector3d& p, double* tau_io = nullptr);

struct SmoothTubeFitParams {
  int max_iterations = 30;
  std::size_t max_points = 2500;  // evenly strided subset used by the fit (0: all; the fillet's too)
  double min_noise_mm = 0.05;     // floor of the robust residual scale
  double kernel_factor = 2.5;     // Cauchy scale = kernel_factor x robust sigma of the residuals
  double peak_fraction = 0.5;     // the curvature's peak is sought over |tau| <= this (the window's middle)
  const NoiseCorrelation* noise = nullptr;  // as FilletFitParams::noise
};

struct SmoothTubeFit {
  bool ok = false;                // converged, the tube radius positive and the peak finite
  SmoothTubeModel model;
  double bend_radius_mm = 0.0;    // 1 / the largest curvature over |tau| <= peak_fraction
  double bend_radius_se_mm = 0.0; // its standard error (Gauss-Newton covariance, delta method)
  double noise_inflation = 1.0;   // its variance over what independent noise gives (SmoothTubeFitParams::noise)
  double peak_tau = 0.0;          // where
  Eigen::Vector3d peak_point = Eigen::Vector3d::Zero();
  double sigma_mm = 0.0;          // robust sigma (1.4826 MAD) of the residuals
  double rms_mm = 0.0;            // Cauchy-weighted RMS
  std::size_t points = 0;
};

// Robust cost (Cauchy, scale `scale_mm`, the same as fillet_robust_cost's) of the points against the model.
double smooth_tube_robust_cost(const std::vector<Eigen::Vector3d>& points, const SmoothTubeModel& model,
                               double scale_mm);

// Fits the smooth tube to the surface points lying over the chord from `a` to `b` (points of the centreline
// window's two ends): the initial curve is the least-squares quartic through `centreline` (the window's
// centreline samples), the initial tube radius `tube_radius_mm`. Points projecting outside the chord are not
// used. Deterministic.
SmoothTubeFit fit_smooth_tube(const std::vector<Eigen::Vector3d>& surface_points,
                              const std::vector<Eigen::Vector3d>& centreline, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, double tube_radius_mm, const SmoothTubeFitParams& params = {});

// The same fit from a given model (the window and frame fixed): a refit on other points.
SmoothTubeFit fit_smooth_tube_from(const std::vector<Eigen::Vector3d>& surface_points, const SmoothTubeModel& initial,
                                   const SmoothTubeFitParams& params = {});

}  // namespace ewis
