#pragma once
// Bend radius of a measured cable (paper 4.3.1), two ways:
//  - measure_bend_radius: the TRUE 3D measure reported in report.json: the radius of curvature along the
//    measured centreline from local circle fits (DESIGN.md "Measurement lessons": a smoothing spline is
//    biased low by 2-8%, local circle fits over about +-2 diameters are not). Each window starts at
//    +-min_half_window_diameters of arc length around its centre and grows on each side while the curve
//    stays a circle within the centreline's own noise, so constant-radius bends are fitted over their whole
//    arc (less noise) and S-bends or bend-to-straight junctions stop the growth.
//  - paper_bend_radius: the paper's figure: the chain's start/end points projected on the plane
//    perpendicular to the sensor's optical axis, a circle by RANSAC (seeded). Kept as an extra number.
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "ewis/core/cylinder.hpp"

namespace ewis {

struct BendRadiusParams {
  double min_half_window_diameters = 2.0;  // smallest window: +-2 diameters of arc length ...
  double min_half_window_mm = 15.0;        // ... and at least +-15 mm (thin cables: a trace's wiggles of a
                                           // tenth of a mm would read as tight bends in shorter windows)
  double sample_step_diameters = 0.125;    // the centreline is resampled at this arc-length step
  double centre_step_diameters = 0.25;     // spacing of window centres
  // A tight bend (turning more than short_window_turn_rad within the smallest window) is shorter than that
  // window, which then takes in straight run and reads high: such a window restarts from +-short_half_window
  // diameters (and at least half the smallest window) when that is one circle, and grows from there.
  double short_window_turn_rad = 1.0;
  double short_half_window_diameters = 1.0;
  double grow_fraction = 0.125;            // one growth step adds this fraction of the window's length
  double grow_total_factor = 1.5;          // growth accepted while the window's RMS <= this x noise ...
  double grow_extension_factor = 1.0;      // ... and the added stretch's RMS <= this x noise x (1 + 3/sqrt(k))
  double min_noise_mm = 0.02;              // floor of the centreline noise estimate (noise-free input)
  // A window is straight (no radius) when its radius exceeds straight_limit_diameters x diameter, or when the
  // fitted arc's sagitta over the window is below sagitta_noise_factor x noise (a circle fitted to noise).
  double straight_limit_diameters = 100.0;
  double sagitta_noise_factor = 4.0;
  // The minimum is taken over radius + selection_se_factor x its standard error, then the radius itself is
  // reported: the minimum of many noisy short-window radii is biased low, a long window in the same bend is
  // precise; this picks the precise fit unless a short one is really tighter.
  double selection_se_factor = 3.0;
};

struct BendSample {
  double arc_mm = 0.0;                                         // window centre, arc length from the start
  Eigen::Vector3d point = Eigen::Vector3d::Zero();             // centreline point there
  double radius_mm = std::numeric_limits<double>::infinity();  // fitted radius; infinity when straight
  double radius_se_mm = 0.0;                                   // its standard error
  double window_start_mm = 0.0, window_end_mm = 0.0;           // the final (grown) window
};

struct BendRadiusResult {
  // Smallest radius of curvature of the centreline (mm); nullopt when the cable is straight everywhere.
  std::optional<double> min_radius_mm;
  double min_radius_se_mm = 0.0;                               // its standard error (from the fit's covariance)
  bool min_radius_is_bound = false;  // the minimum is an upper bound: a kink too short for its radius to be measured,
                                     // at the loosest radius its surface points allow (bend_refine, fillet_fit.hpp)
  double min_radius_fit_mm = 0.0;    // with min_radius_is_bound: the free fit's radius under the bound (at least the
                                     // tube's), min_radius_se_mm of it per FilletRefineParams::bound_log_likelihood_ratio
  // Which model the minimum comes from: "circle" (the centreline's circle windows), "fillet" (line-arc-line on the
  // surface, fillet_fit.hpp), "bound" (a kink's upper bound) or "smooth" (quartic tube, smooth_tube_fit.hpp).
  const char* min_radius_model = "circle";
  std::optional<Eigen::Vector3d> location;                     // where (middle of the minimum's window)
  double location_arc_mm = 0.0;
  Eigen::Vector3d circle_center = Eigen::Vector3d::Zero();     // the minimum's fitted circle (for pictures)
  Eigen::Vector3d circle_normal = Eigen::Vector3d::UnitZ();
  double noise_mm = 0.0;                                       // centreline noise estimate used
  double length_mm = 0.0;                                      // centreline length
  std::vector<BendSample> profile;                             // one per window centre, along the cable
};

// `centerline`: ordered points (any spacing; duplicates are skipped). Deterministic for any thread count.
BendRadiusResult measure_bend_radius(const std::vector<Eigen::Vector3d>& centerline, double diameter_mm,
                                     const BendRadiusParams& params = {});

struct PaperBendParams {
  double inlier_mm = 0.0;                  // <= 0: max(0.5 mm, 0.05 x diameter)
  int iterations = 1000;
  double max_radius_diameters = 100.0;     // circles larger than this are straight runs, not bends
  std::uint64_t seed = 1;
};

struct PaperBendResult {
  std::optional<double> radius_mm;         // nullopt: no circle (too few points, or straight)
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  // circle centre, back in 3D (on the points' mean plane)
  std::size_t inliers = 0;
  std::size_t points = 0;
};

// paper 4.3.1: P_s and P_e of every sub-cable, projected on the plane perpendicular to `optical_axis`
// (unit, same frame as the chain), circle by RANSAC.
PaperBendResult paper_bend_radius(const std::vector<Cylinder>& chain, const Eigen::Vector3d& optical_axis,
                                  double diameter_mm, const PaperBendParams& params = {});

}  // namespace ewis
