#pragma once
// Bend radius from the cable's SURFACE points with a line-arc-line (fillet) model: two straight legs joined by a
// circular arc tangent to both, the shape of a routed cable bend (and of most CAD routes), swept by the tube
// radius. Why (paper 4.3.1, DESIGN "Measurement lessons"): circle fits to a centreline need an arc several
// diameters long; a short tight bend (tens of degrees at a few diameters: an arc shorter than one diameter) is
// a corner to any window and to the chain itself, and its radius reads high. Its radius shows only in how far
// the surface leaves the two legs' corner (R (1 / cos(turn / 2) - 1), a fraction of a mm), which hundreds of
// surface points measure and a dozen noisy chain joints do not.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "ewis/core/cloud.hpp"
#include "ewis/inspect/bend_radius.hpp"
#include "ewis/inspect/smooth_tube_fit.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis {

struct FilletModel {
  Eigen::Vector3d vertex = Eigen::Vector3d::Zero();  // where the two legs' lines meet
  Eigen::Vector3d leg1 = Eigen::Vector3d::UnitX();   // unit, from the vertex back along the incoming leg
  Eigen::Vector3d leg2 = -Eigen::Vector3d::UnitY();  // unit, from the vertex along the outgoing leg
  double bend_radius_mm = 1.0;                       // of the arc (centreline): 1 / its curvature
  double tube_radius_mm = 1.0;
  // A bend out of its plane (a cable routed in 3D): the arc is a helix of the same curvature tangent to both legs,
  // its axis tilted by tilt_rad from the legs' plane's normal towards the direction from leg1 to leg2 (0: the
  // planar arc; the legs are then skew, and `vertex` is the middle of their common perpendicular). Why: a planar
  // arc cannot follow a helical bend's torsion, and where the smooth tube could (smooth_tube_fit.hpp) it won the
  // choice by that alone and read the helix's ends as tighter bends (campaign scene_113: a helix of 71.4 mm read
  // 67.7 +- 0.4 mm, fillet 71.1).
  double tilt_rad = 0.0;
  double turn_rad() const;                           // direction change over the arc (pi - angle between legs)
};

// Distance from p to the model's centreline (legs as half-lines from the arc's tangent points).
double fillet_centreline_distance(const FilletModel& m, const Eigen::Vector3d& p);

// A tilted fillet's arc: the helix X(phi) = axis_point + rho (-cos(phi) e_n0 + sin(phi) e_t0) + lift phi n, phi in
// [0, phi_end], of curvature 1 / bend_radius_mm, tangent to -leg1 at `start` and to leg2 at `end`.
struct FilletHelix {
  Eigen::Vector3d axis_point, n, e_t0, e_n0, start, end;
  double rho = 0, lift = 0, phi_end = 0;
  Eigen::Vector3d at(double phi) const;
};

// A model's centreline worked out once for the distances of many points (the fits evaluate thousands per model:
// the tangent points, the arc's centre and the helix are the same for all of them).
struct FilletShape {
  bool helical = false;  // the helix below, else the planar arc
  FilletHelix helix;
  Eigen::Vector3d leg1, leg2, t1, t2;  // the legs' directions and their starts (the arc's or helix's ends)
  bool has_arc = false;                // a planar arc to measure to (not degenerate)
  Eigen::Vector3d centre, n, ea, eb;   // its centre, unit normal, and the spokes to t1 and t2
  double bend_radius_mm = 0, s_ab = 0;
};
FilletShape fillet_shape(const FilletModel& m);
// The same as fillet_centreline_distance(m, p) for the model `shape` was made from.
double fillet_shape_distance(const FilletShape& shape, const Eigen::Vector3d& p);

struct FilletFitParams {
  int max_iterations = 40;
  std::size_t max_points = 2500;      // evenly strided subset used by the fit (0: all)
  double min_noise_mm = 0.05;         // floor of the robust residual scale
  double kernel_factor = 2.5;         // Cauchy scale = kernel_factor x robust sigma of the residuals
  bool fit_tube_radius = true;
  bool fit_bend_radius = true;        // false: the bend radius stays at the initial one (a competing hypothesis)
  bool fit_tilt = false;              // true: the arc may be a helix (FilletModel::tilt_rad); false: it stays as given
  // Noise that neighbouring points share (filter/noise_correlation.hpp; null: independent). The radius's standard
  // error counts it (FilletFit::noise_inflation: the variance of the points' influences on the radius summed under
  // the scan's correlation, correlated_inflation), and refine_bends_with_fillets divides the likelihood ratios about
  // a fit's radius by that fit's inflation.
  const NoiseCorrelation* noise = nullptr;
};

struct FilletFit {
  bool ok = false;                    // converged to a bend (turn > 0, finite radius)
  FilletModel model;
  double rms_mm = 0.0;                // robust (Cauchy-weighted) RMS of the surface residuals
  double sigma_mm = 0.0;              // robust sigma (1.4826 MAD) of the residuals
  double bend_radius_se_mm = 0.0;     // standard error of the bend radius (Gauss-Newton covariance)
  double noise_inflation = 1.0;       // the radius's variance over what independent noise gives (FilletFitParams::noise)
  int iterations = 0;
  std::size_t points = 0;
};

// Sum of the Cauchy costs (scale `scale_mm`) of the surface residuals of `points` against the model: two models
// compare on the same points and scale (a likelihood ratio under a robust noise model).
// `noise_scale` (optional, one per point; ignored when its size differs): each residual is divided by it (a point's
// noise relative to the others', see ray_noise_scales).
double fillet_robust_cost(const std::vector<Eigen::Vector3d>& points, const FilletModel& model, double scale_mm,
                          const std::vector<double>* noise_scale = nullptr);

// Least-squares fit (Levenberg-Marquardt, Cauchy-weighted) of the swept fillet to surface points, from `initial`.
// Deterministic. With `noise_scale` (one per point) the residuals are divided by it: a weighted fit, whose sigma and
// standard error are those of the scaled residuals.
FilletFit fit_fillet(const std::vector<Eigen::Vector3d>& surface_points, const FilletModel& initial,
                     const FilletFitParams& params = {}, const std::vector<double>* noise_scale = nullptr);

// The noise of each point relative to the others' (median 1) on a tube fitted by `model`, seen from `sensor`: a
// structured-light sensor's noise lies along its rays, so across the surface a point's residual spreads as
// sigma x cos(incidence) where the surface turns away, and isotropic noise spreads the same everywhere. Both
// parts are measured on the residuals (variance = a + b cos^2, a, b >= 0, from the robust spreads in four bins of
// cos^2); the scale is sqrt(variance), at least half that of a point seen face on (weights at most 4x).
std::vector<double> ray_noise_scales(const std::vector<Eigen::Vector3d>& points, const FilletModel& model,
                                     const Eigen::Vector3d& sensor);



struct FilletRefineParams {
  bool enabled = true;
  // A candidate's fit stopped by its iteration limit (inside a long arc its legs lie beyond the window and the
  // vertex slides along a flat direction) counts as converged when a second run from it leaves the radius within
  // 0.05 of its standard error and that is under narrow_max_se_fraction of it (as the narrower fillet's); it is then
  // taken as it is unless it reads tighter than the circle windows by over 2 standard errors (then the likelihood
  // tests of an imprecise fit decide). False: the circle windows' figure stands for it.
  bool settle_unconverged = true;
  int max_candidates = 6;             // bends re-measured per run (the tightest windows of the circle profile) ...
  double max_radius_ratio = 5.0;      // ... whose circle radius is within this factor of the tightest one's
  // ... and before them, up to max_corner_candidates corners: peaks of the centreline's turn between the chords
  // over +-corner_span_diameters whose prominence (the turn's rise above the higher of the lowest points on each
  // side before a higher peak) is at least corner_min_turn_deg, most prominent first (a short tight bend reads
  // nearly straight to the circle windows; a long arc's turn is a plateau whose noisy peaks are not prominent).
  // 1 diameter: a short bend between long arcs keeps straight runs around it at that span (at 2 d the chords
  // reached into its neighbours, and the long arcs' plateau peaks took every slot).
  int max_corner_candidates = 4;
  double corner_span_diameters = 1.0;
  double corner_min_turn_deg = 8.0;
  double leg_diameters = 2.0;         // each window reaches this far beyond the circle window's half-length ...
  double min_half_window_diameters = 3.0;  // ... and at least this far from the bend's centre
  // A leg must be straight. A leg (from the fit's tangent point to the window's end) is bent where the centreline
  // over its outer quarter strays from the leg's line by more than leg_max_sagitta_mm or leg_sagitta_noise_factor x
  // the centreline's noise (BendRadiusResult::noise_mm; straight legs on the campaign: up to about 4x), as when the
  // window reaches into the next bend (a local wiggle of the chain, at a clamp, strays in the middle: with the whole
  // leg tested, one 1.5x-noise scene's straight leg was cut to a diameter and its bend read 3.9 -> 7.3 % low). The
  // window is then cut back to where the centreline leaves the line of the leg's near part (its first third, at least
  // leg_min_diameters) by that much, at the last sample still within a third of it, and the bend fitted again there
  // (its refit on the scan kept to points along the window), twice at most (the second from the new fit's tangent
  // points). 0: off. Campaign scene_106: a 58 mm arc, 11.5 mm of straight, then a 124 mm arc; the window's second
  // leg took 25 mm of the loose arc and read 52.4 mm.
  double leg_max_sagitta_mm = 0.15;
  double leg_sagitta_noise_factor = 6.0;
  double leg_min_diameters = 1.0;
  // A fillet with both tangent points inside its window and a leg shorter than min_seen_leg_diameters there is kept
  // only where the centreline from that tangent point on, over min_seen_leg_reach_diameters past the window's end, is
  // a straight line (its stray from the line fitted to it within the leg test's limit above), or, where it is not,
  // lies closer to the leg's line than to the fit's circle continued (arc_goes_on_past_leg: a short straight into
  // the next bend, not the same arc going on); where the run ends first, it is not kept (a tangent point beyond the
  // window's end leaves arc only on that side: a fit of the arc, kept). A refused candidate is dropped whole, its
  // smooth tube too (its window cuts the bend; another candidate's holds it).
  // A window whose centre lies off the bend holds only part of a long arc; the fit then lays a "leg" on the arc's last
  // few mm, and with the turn fixed by that leg's direction the arc is too short and reads tight (fresh campaign seed
  // 6262 scene_050: a 50 deg arc of 78.9 mm on a 23 mm hose, its run starting 2.4 d before it, read 66.3 +- 2.0 from
  // the window of the run's first sample, over the straight and the arc's first 38 mm, its second leg 5 mm long; the
  // centreline past it strays 3.6 mm from a line over 3 d against a limit of 2.3). Judged on the model's own leg
  // direction instead, a good fit with a 0.8 mm leg was refused (its leg direction, from so little leg, was 5 deg off);
  // refusing every short leg cost a seed 5151 bend (40.96 -> 45.85 for 40.90: legs of 0.4 and 1.2 mm on straights).
  // Refusing every continuation that is not straight cost a spline's peak (S20 scene_006: 68.9 -> 75.0 for 67.9, its
  // window's 1.9 mm leg running into the spline's falling curvature) and refused a 157 mm arc's exact fit (N
  // scene_050: 88.13 +- 0.11 for 88.1, a 0.3 mm leg, then 10 mm straight and a 107 mm arc); keeping the smooth tube
  // of a refused candidate read N scene_050's 88 mm arc's onset as 80.1 (the quartic's overshoot at a curvature step).
  double min_seen_leg_diameters = 0.5;
  double min_seen_leg_reach_diameters = 3.0;
  // That test judges the continuation on the centreline alone, which a thin cable's short arc does not settle: a
  // window centred 36 mm before a 40 deg, 28.7 mm arc of a 3.4 mm cable (campaign scene_069, a corner candidate where
  // the circle windows read straight) ended 7 mm into the arc; its fit laid its arc over the arc's first 12 mm with a
  // 0.3 mm leg and read 24.34 +- 1.18, and the centreline over 3 d past it strayed 0.30 mm from a line (limit 0.64)
  // and lay nearer the leg's line than the fit's circle. So also: a fillet whose arc ends within
  // min_seen_leg_diameters of a window end that is not the run's end, at a point inside the arc of another
  // candidate's fillet whose both legs are seen in its window and whose radius is known at least as well, is left
  // out of the choice: its window cut that bend,
  // the other's holds it whole (there 28.86 +- 0.48 for 28.75). See arcs_cut_by_their_windows. False: off.
  bool cut_arcs_held_elsewhere = true;
  // A leg running to the centreline's end (a run's end, where the centreline's own leg tests above cannot look past)
  // must lie along its points: the axis that its surface points (those within 3 Cauchy scales of the model, at least
  // leg_drift_min_points) are fitted around, as the leg's line moved by a + b t across it (t along the leg, the
  // residuals linear in a and b), may not walk away from the leg by more than leg_drift_max_mm over its length (|b| x
  // length) with a chi-square of b over leg_drift_min_z^2. (A mean residual does not show it: a leg moved sideways
  // brings one flank of the tube closer and the other farther.) Where it does, the window's end on its side is brought
  // in to half the leg and the fillet fitted again, and the refit is taken if its leg lies along its points. H40
  // scene_021 (a fresh set of the thirty-fourth session): a 23.3 mm hose's 15.7 deg kink of 67.50 mm, 57.5 mm after a
  // 205.6 mm arc, read 44.70 +- 7.56 from the window at its run's end, whose 103 mm leg ran over that arc (0.64 mm off,
  // z 19); refitted, 64.92 +- 3.42. The size floor was 0.5 mm: once the scene's bracket was wound outward (thirty-
  // eighth session, scene/orient_faces.hpp) the registration moved by 0.02 mm at the cables and the same leg drifted
  // 0.49 mm at z 15, so the window stood (48.28 +- 6.87); at 0.4 mm it is refitted, 63.17 +- 3.89, and of the other
  // reports of C (140), H40, S20 and S30 one moved (C scene_085: 91.55 -> 91.47 for 91.60). Refusing the candidate when the refit's leg walks off too mended H40 scene_029
  // (a crossing cable hides the middle of a 70.97 mm arc; a window at the run's end, its points gathered again past
  // the end, read the arc's seen start as a 17 deg corner of 43.68 +- 3.76, truth 55.24) but cost the spline sets a
  // missed bend defect (S30 scene_019: 43.35 -> 62.63 for 38.73) and S20 scene_005 (68.04 -> 75.98 for 65.62): a
  // fillet only approximates a spline's varying curvature, whose legs walk off; judging every leg moved 9 of the 70
  // spline scenes' minima, 7 away from the truth. leg_drift_inside: both legs of every window (off; on for the fits
  // across a gap between runs, whose legs may lie where nothing was traced: RunJoinParams::fillet_leg_drift_inside).
  // docs/inspect.md. <= 0: off.
  double leg_drift_max_mm = 0.4;
  bool leg_drift_inside = false;
  double leg_drift_min_z = 8.0;
  std::size_t leg_drift_min_points = 30;
  double min_turn_deg = 4.0;          // a fit turning less is a straight run, not a bend
  // ... and one turning more than the centreline does across its window (its legs' lines, from the window's outer
  // thirds) by over max(max_turn_excess_deg, max_turn_excess_fraction x that turn) fits something else: a stereo-
  // mismatch patch at a run's end (M40 scene_038 without a pose: a 162 deg hairpin of 2.78 mm where the centreline
  // turns 24 deg). Over 1 368 fits taken on C, S25x, B25x and X30s the excess was at most 49 deg (37 on C: inside long
  // arcs, whose outer thirds' lines turn less than the whole window; 49 where a window starts inside a bend).
  double max_turn_excess_deg = 60.0;
  double max_turn_excess_fraction = 1.0;
  double max_se_fraction = 0.15;      // the fit's radius must be known to this fraction (1 standard error) ...
  double max_se_fraction_vs_circle = 0.5;  // ... or to this one when it lies over 2 standard errors below the
                                           // circle windows' radius there AND the data prefer it: the same model
                                           // held at the circle's radius fits worse by a likelihood ratio over
                                           // min_log_likelihood_ratio (2 x cost difference / sigma^2, chi-square 1;
                                           // 25: five standard errors, as for the doubled radius below. It was
                                           // 100: the 1.7 d bend of a 4 mm cable, fitted at 15-16 %, was refused in
                                           // 13 of 20 rescans; at 25 in 6, with no change on either campaign)
  double min_log_likelihood_ratio = 25.0;
  // ... and the same model held at twice the fit's radius fits worse by at least this ratio (the radius is
  // bounded on the loose side too; 25: five standard errors)
  double min_log_likelihood_ratio_doubled = 25.0;
  // A fit the data prefer to the circle windows' radius but do not pin down (or tighter than the tube: a short kink)
  // is reported at the loosest radius the data allow: where the ratio reaches bound_log_likelihood_ratio (6.25: a
  // 2.5-sigma bound; the true radius lies above it about once in 160 on a right model), found by bound_iterations
  // bisection steps (on a log scale) between the fit's radius and the circle windows'. An upper bound answers the
  // check "at least the allowed radius" for a kink whose radius no fit pins down: campaign scene_031's 12 deg kink of
  // 15.1 mm on a 13.2 mm cable (limit 66 mm) reads at most 36.4 mm, where the circle windows read 139 mm. It was 9
  // (3 sigma, once in 740): the second scanner's scene_001 (bench/second_scanner.py; a 13.8 deg kink of 21.5 mm on a
  // 13.7 mm cable, limit 34.25 mm) read at most 34.99 mm, a missed defect; at 6.25, 32.75. A bound reading below the
  // limit still needs the fit to put the radius there with 99.4 % confidence, and a clean cable's bends lie above it.
  double bound_log_likelihood_ratio = 6.25;
  int bound_iterations = 10;
  // ... and only when the fit turns as the centreline does across the window (the legs' lines fitted to its outer
  // thirds), within this many degrees or this fraction of that turn (real kinks: within 0.05 deg)
  double bound_turn_tolerance_deg = 3.0;
  double bound_turn_tolerance = 0.25;
  double tube_radius_tolerance = 0.25;  // the fitted tube radius within this fraction of the measured one
  // The cable's point set S comes from a chain of straight cylinders, which cuts a tight bend's corner and so
  // leaves out the outer surface at its apex: the very points that carry the radius. With the scan given, the
  // fit is repeated on every usable scan point within the tube radius + regather_band of the first fit's surface
  // (band <= 0: max(3 x the fit's sigma, 0.25 x tube radius, 0.5 mm)).
  bool regather = true;
  double regather_band_mm = 0.0;
  // With the sensor known (FilletScan::has_sensor), the refit on the scan keeps only the points whose outward
  // direction from the first fit's axis turns towards the sensor (cosine at least facing_min_cos), as the
  // tubes' cylinder fits do: a sensor sees only the near side of a tube. The mixed pixels under the silhouette
  // of a cable lying on a plate hang in the wedge between its unseen underside and the plate, within a few
  // tenths of a mm of the tube's surface and all on one side of it: 55 such points of 1774 (3 %) read campaign
  // scene_059's 41.85 mm bend at 38.72 +- 0.93 mm with a tube 0.25 mm too fat; without them 41.59 +- 0.74.
  double facing_min_cos = 0.0;
  // ... and weighs each point by its noise across the surface (ray_noise_scales: a structured-light sensor's noise
  // lies along its rays, so a point where the tube turns away from the sensor is placed more precisely across it).
  bool ray_noise_weights = true;
  FilletFitParams fit;
  // Smooth bends. A cable routed along a spline bends with a curvature that rises and falls; the line-arc-line
  // model (and the circle windows) average its peak away (bench/spline_scenes.py: 0 of 33 bends within 5 %, all
  // high). Each candidate is also fitted with a smooth tube (smooth_tube_fit.hpp) over +-smooth_window_radius_fraction
  // x its radius (at least smooth_min_half_window_diameters, at most smooth_max_half_window_diameters), recentred
  // once on the peak it finds, on the scan points around it. Its radius is taken when the data prefer it to the
  // fillet refitted on the same points by a likelihood ratio of at least smooth_min_log_likelihood_ratio (2 x cost
  // difference / sigma^2; the smooth tube has two parameters more, so a fillet-shaped bend gives about 2, and 25
  // is five standard errors as for the fillet's own tests), and it is known to max_se_fraction.
  bool smooth = true;
  // ... known to smooth_max_se_fraction (1 standard error), tighter than a fillet (max_se_fraction): the quartic is the
  // freer model, and its peak a local reading that outliers bend. Of the 173 cables read by a smooth tube over 15 sets
  // (C, H40, K40, S30, S20, B20, two hose sets, seven dark-cable sets) none was known worse than 4.1 %; under a halo of
  // 40 % of the points moved by a Gaussian 1.5 mm in any direction (the forty-first session's RI1 scene_003) a quartic
  // read 37.54 +- 4.53 mm (12 %) for a 56.24 mm bend: 51.15 +- 1.91 by the fillet with this cap.
  double smooth_max_se_fraction = 0.08;
  double smooth_window_radius_fraction = 0.5;
  double smooth_min_half_window_diameters = 1.0;
  double smooth_max_half_window_diameters = 3.0;
  // A wider window: where the candidate's radius allows one wider than smooth_max_half_window_diameters (+-0.5 R, up to
  // smooth_wide_max_half_window_diameters, at least 1.25 times the first), the smooth tube over it, centred on the
  // first one's peak, replaces the first when its own peak lies in its middle (as the recentring asks of the first),
  // - its model explains the first window's points about as well as the first fit does: 2 x the robust cost's rise
  //   on them / sigma^2 at most smooth_wide_max_log_likelihood_ratio (the first fit has 11 parameters free there, so
  //   a right wider model gives about 11; one stretched over a curvature's step or a spline's tails, 40-1000);
  // - and the two radii differ by at most smooth_wide_max_z standard errors of the difference, sqrt(se_first^2 -
  //   se_wide^2), at least se_first / 2 (nested windows, as for narrow_min_z).
  // Why: on a thin cable +-3 d is a short window against a spline's peak (4 mm: +-12 mm), its quartic reads with a
  // standard error of 5-10 % and loses to the fillet, whose wider window averages the peak (S30 scene_008 cable_B,
  // 5.3 mm, truth 62.7: fillet 69.10 +- 0.47, smooth tube over +-16.5 mm 63.33 +- 3.41 at a likelihood ratio of 2.2;
  // over +-33 mm 63.44 +- 0.60, taken). Raising smooth_max_half_window_diameters to 6 instead (no tests) left S30 at
  // 33 of 53 within 5 % and S20 at 18 of 33 (19): as many lost as gained, e.g. S30 scene_013 cable_A 97.8 -> 106.4
  // for 95.7, where the lack of fit is 125. With the lack-of-fit test alone 37 of 53, but campaign C scene_015's
  // 70.2 mm helix read 63.14 +- 0.40 where the first window read 66.82 +- 1.18 (3.3 standard errors apart; lack of
  // fit 18.8). 0: off.
  double smooth_wide_max_half_window_diameters = 6.0;
  double smooth_wide_max_log_likelihood_ratio = 25.0;
  double smooth_wide_max_z = 3.0;
  double smooth_min_log_likelihood_ratio = 25.0;
  // A smooth tube taken (by the tests below) is fitted again over narrower windows around its peak, each
  // smooth_narrow_factor times the last, down to smooth_narrow_min_half_window_diameters, at most smooth_narrow_max_steps
  // times; a narrower one replaces the last where its radius is tighter by at least smooth_narrow_min_z standard errors
  // of the difference (sqrt(se_narrow^2 - se_wide^2), at least se_narrow / 2, as for narrow_min_z), it is known to
  // smooth_narrow_max_se_fraction, its tube within smooth_tube_radius_tolerance and its peak smooth_min_end_diameters
  // from the run's ends. Why: a spline's curvature may peak within a diameter (S30 scene_017 cable_A, 12.8 mm: 53.6 mm
  // at its peak, 64-70 mm 5 mm either side), and a quartic over +-0.5 R (here 2.5 d) averages it: noise-free, the
  // quartic over the truth's centreline reads it 14.7 % high, over +-1 d 6.4 %. On an arc the narrower windows read
  // the same radius. 0 steps: off.
  int smooth_narrow_max_steps = 3;
  double smooth_narrow_factor = 0.7;
  double smooth_narrow_min_half_window_diameters = 1.0;
  double smooth_narrow_min_z = 2.5;
  double smooth_narrow_max_se_fraction = 0.035;
  // ... or of at least smooth_varying_min_log_likelihood_ratio (9: three standard errors) where the curvature
  // varies along the bend: the fillet refitted on the smooth tube's points (a narrower window) reads tighter than
  // the candidate's own fillet by at least smooth_varying_min_z of its standard errors. On an arc a fillet reads
  // the same radius over any window that holds it; on a spline the narrower window sees more of the peak. With
  // the lower threshold alone, S20 had 20 of 33 bends within 5 % (15 before) but the campaign C 179 of 193 (182):
  // five arcs read 3-11 % low by the smooth tube, each with its two fillets within 1 se of each other, where the
  // spline bends gained showed 2-12 se.
  double smooth_varying_min_log_likelihood_ratio = 9.0;
  double smooth_varying_min_z = 2.0;
  // ... and only when its tube radius is within this fraction of the run's measured one: a smooth fit with a
  // wider tube holds points of something else (campaign scene_113: a run's end by a connector, 7.35 for 6.75 mm,
  // read a 71.3 mm helix at 64.4 mm)
  double smooth_tube_radius_tolerance = 0.05;
  // ... and only when its peak lies at least smooth_min_end_diameters from the run's start and end (along the
  // centreline): the chain's last joints and the surface there are the least reliable (a run ends where the cable
  // enters a connector or clamp, or something hides it), and the quartic, free at a window's clipped end, turns
  // that into a peak (H60 scene_052: a 10.9 mm cable's helix read 27.48 +- 0.39 at 0.7 d from its run's start,
  // where the arc's fillet reads 46.3; with this rule the cable reads 41.2 for its tightest bend, 41.05). On the nine
  // sets evaluated only one other reading moved: S25x scene_016's cable_B, whose two smooth readings near its run's
  // start were both imprecise (116.51 +- 6.96 at 0.95 d, taken before; 123.35 +- 5.19 at 1.1 d; truth 115.90).
  double smooth_min_end_diameters = 1.0;
  // A candidate whose fillet is refused for a leg unseen (min_seen_leg_diameters: its window cuts the bend) still has
  // its smooth tube tried, weighed against that fillet as above, where no other candidate's fillet reading holds the
  // place (between its tangent points, a diameter either side); where one does, the candidate is left out whole, as
  // before (a smooth tube over an arc's onset read N scene_050's 88 mm arc at 80.1 where another window's fillet held
  // it at 88.13). Why: a short run that is one smooth bend (a hose between two clamps) leaves no window with both legs
  // seen, and the circle windows' average stood: bench/spline_scenes.py with hoses of 18-30 mm (32 scenes made for the
  // fortieth session), a 30.2 mm hose's 95.24 mm peak on a run of 128 mm read 113.59 -> 96.02 +- 0.45, and 143.16 read
  // 190.03 -> 141.18; S30 scene_018 cable_A 152.33 -> 146.65 for 147.59; no other report of C (140), H40, S30, S20 or
  // B20 moved. false: refused whole.
  bool smooth_cut_unheld = true;
  // ... and only where its points show its peak: over smooth_peak_seen_diameters either side of the peak (along the
  // chord) each side holds at least smooth_peak_seen_fraction of the points its share of the window would hold at the
  // window's mean density. A quartic is free where the scan has a hole and may bend there (a sensor's dropout on a
  // dark jacket, bench/dark_cables.py: a 6.2 mm cable of C scene_012 with half its points taken away in blobs read
  // 10.32 +- 0.73 for a 41.94 mm bend, a false alarm, its peak with 6 points within a diameter before it and 72
  // after, against about 30 expected each side: now 64.78 by the fillet, and no false alarm); where the data show the
  // peak, each side holds about its share, and no reading of C (140), H40, S30, S20, B20 or 32 hose scenes moved.
  // The price: over a clean hole the quartic's peak read from one side is right, and the fillet stands instead (a few
  // percent loose; FilletRefine.ASmoothPeakInAHoleIsNotTaken). 0: off.
  double smooth_peak_seen_diameters = 0.5;
  double smooth_peak_seen_fraction = 0.5;
  // ... and, where the fillet refitted as a helix (FilletModel::tilt_rad free) on the same points fits about as well
  // as the smooth tube (likelihood ratio under smooth_tilted_max_log_likelihood_ratio: the quartic has one parameter
  // more, so a helical bend gives about 1), only where the curvature varies as the helices read it: the helix on the
  // smooth tube's points reads at least smooth_varying_min_z of its standard errors, and at least
  // smooth_tilted_min_variation of the radius, tighter than the helix refitted on the candidate's wider window (on a
  // helix of 71.4 mm the two read 0.4 % apart at 3 se: the narrower one across an end). Why: a planar arc cannot
  // follow a helical bend's torsion and the quartic can, so the smooth tube won on it by the likelihood ratio alone,
  // and over windows across the helix's ends, where a quartic overshoots a curvature that steps, read it low
  // (campaign scene_113: 67.7 +- 0.4 mm for a 71.4 mm helix; scene_100: -4.6 %). There the helix fitted the points
  // as well as the quartic or better (ratios -280 to 2). On the spline set S20 the helix took a spline's twist with
  // an extreme tilt (1.1-1.2 rad) and left the quartic ratios of 5-15: with the threshold that had applied (25, or 9)
  // in place of 4, S20 lost 1 (with the variation test) or 6 (without) of its 19 bends within 5 %; at 4 none moved.
  // false: the planar fillet only.
  bool smooth_tilted_rival = true;
  double smooth_tilted_max_log_likelihood_ratio = 4.0;
  double smooth_tilted_min_variation = 0.01;
  // ... and only when its peak radius is at least this fraction of the fillet's refitted on the same points: a
  // curvature that rises and falls within the window peaks at about 1.5 (a quadratic profile) to 2 (a triangle)
  // times the window's mean, which the fillet reads. Over 351 smooth fits taken on 70 spline scenes the ratio was
  // 0.63-1.0; at a run's end by a connector, where the seen arc narrows to the cable's top strip, a quartic bent its
  // axis to follow it and read 130 mm for a 244 mm cable (fillet 307 mm: 0.42), a false bend alarm
  // (bench/spline_scenes.py --bundle 3, seed 7, scene_012).
  double smooth_min_fillet_ratio = 0.5;
  // ... and only when it does not buy its advantage in one stretch by fitting worse elsewhere: with the points over
  // the chord in smooth_spread_bins equal stretches (by the chord's parameter), the likelihood ratio over all but the
  // stretches where the smooth tube gains most (smooth_spread_top_bins) must reach
  // smooth_spread_min_log_likelihood_ratio (0: the rest of the window fits at least as well as by the fillet). A
  // touching object's points give the quartic its whole advantage in one stretch and the rest fits worse: I60
  // scene_035, a box resting 0.57 mm above a 15.8 mm cable in the middle of its 106.27 mm bend, read 92.24 +- 0.62 by
  // the quartic (ratio 48.2: +82.1 in the box's stretch, -33.9 over the rest), the fillet 105.24 +- 0.35; I60
  // scene_015 (a foreign object 0.31 mm from cable_A) 80.29 for 86.24 (+95.2, -11.0). A spline's varying curvature
  // spreads it (S25x, B25x: each stretch 0-15 of totals 9-270; with one stretch set aside the rest was >= 6.8, with
  // two no spline reading changed). 0 or 1: off.
  // The stretches set aside: the smooth_spread_top_bins where it gains most (2: a local flaw of the surface may
  // straddle two stretches). A stereo sensor's mismatch patch (a block of pixels at one wrong depth, docs/sim.md) on a
  // 3.6 mm cable, 32 points 1.4 mm deep: the quartic read 17.42 mm for a 49.74 mm bend (ratio 28.3: +18.5 and +12.9
  // in two neighbouring stretches, -3.1 over the other six), a false bend alarm (campaign seed 4040
  // --mismatch-patches 300, scene_004); with two set aside the fillet reads 49.08.
  int smooth_spread_top_bins = 2;
  int smooth_spread_bins = 8;
  double smooth_spread_min_log_likelihood_ratio = 0.0;
  // A fillet's window over a curvature peak. Where the smooth tube is not taken, the fillet refitted on its points
  // (the narrower window, centred on the peak) reads the candidate when it is tighter than the candidate's own
  // fillet by at least narrow_min_z standard errors of the difference, sqrt(se_narrow^2 - se_wide^2) (nested fits
  // of one model: the Hausman test), at least se_narrow / 2. An arc reads the same over both windows; a spline's
  // peak reads tighter over the narrower one, where both models often misfit it alike and the smooth tube's
  // likelihood ratio stays under 9 (S30 scene_022: fillet 91.11 +- 0.50 mm over 64 mm, 87.05 +- 2.04 over 34 mm,
  // smooth tube 84.67 +- 5.15 at a ratio of 1.6, truth 83.22). Bends of 3-20 d within 5 % on the spline sets
  // S30 / S20 / B30 / T20: 29 / 19 / 14 / 15 without, 33 / 20 / 16 / 17 at 3 (C 184/193, 4 of its 208 bends moved by
  // under 2.5 %); at 2 S30 gained one more, but 15 of C's arcs moved 2-4 % low (the differences on C's candidates
  // run about 1.3 times wider than the formula: 5 of 152 at 2). <= 0: off.
  double narrow_min_z = 3.0;
  // ... and when it is known to narrow_max_se_fraction of its radius: on a thin cable's helix at 0.3 mm noise (the
  // 1.5x noise set N, scene_037: 4.4 mm cable, 48.8 mm helix) a 26 mm window read 34.3 +- 3.0 mm (8.8 %) where the
  // wider one read 50.5 +- 0.7, "5.5 standard errors" that were the short window's bias; the spline peaks that
  // gained read to 1-4 %.
  double narrow_max_se_fraction = 0.05;
  // The cable's minimum is the re-measured bend with the least radius + choice_se_factor x its standard
  // error, so an imprecise fit cannot raise a false alarm on its own. At 2 a short tight arc fitted right
  // (40.7 +- 4.6 mm for a 40.1 mm truth) lost to a long looser one (47.5 +- 1.1 mm) by under 0.5 mm on 3 of
  // 140 campaign scenes; 1.5 keeps them (C: 179/193 within 5 %, was 177) with no false alarm on C, N, S.
  double choice_se_factor = 1.5;
  // A window centred near one end of a longer arc holds only the arc's last stretch: its fillet reads it with a few
  // times the whole arc's standard error, and where it read 1.5-2 of them low it won the choice (the repeatability
  // scene of seed 12, one scan of 20: 35.35 +- 2.27 mm near an 8.5 d arc's end, where the arc's own fit read
  // 40.64 +- 0.07 for 40.63). Such a fit is left out of the choice when another candidate's fillet
  // - is looser and far more precise: its standard error at most explained_max_se_ratio times this one's (two fits
  //   of one arc about as precise are each as good: with 1, a40's scene_038 read 69.6 +- 1.2 mm, not 67.0 +- 1.3,
  //   for 66.6);
  // - has this fit's arc's middle on its arc (between its tangent points, along the centreline);
  // - agrees on the radius: the two differ by less than explained_max_radius_z combined standard errors (arc ends
  //   read 1.5-2.5 low; a spline's curvature peak, which a narrower window reads tighter, 4-15 on the two-cable
  //   bundles);
  // - and is not rejected by this fit's points inside its window (its model as it stands; the same weights and
  //   kernel) by a likelihood ratio of explained_min_log_likelihood_ratio (2 x cost difference / sigma^2; 25: five
  //   standard errors, as for the other tests).
  // explained_min_log_likelihood_ratio <= 0: off.
  double explained_min_log_likelihood_ratio = 25.0;
  double explained_max_radius_z = 3.0;
  double explained_max_se_ratio = 0.5;
  // A candidate no fit re-measured keeps its circle windows' figure, read from the centreline: the chain's joints,
  // one tube radius apart. Within four joints of a run's end they lie 0.04-0.08 mm inside a bend at the median
  // (inside a run 0.027) and 4-19 % of them are more than 0.2 mm off (inside 0.4-1 %; campaigns C and F60), so a
  // circle window reaching there reads tight: campaign scene_136's helix read 51.67 +- 0.61 for 54.79 at the run's
  // end, where no fillet fits for want of a leg (the arc's fillet read 54.70 +- 0.54). Such a figure, whose window
  // reaches within circle_explained_end_diameters of the run's start or end, is left out of the choice where its
  // window's middle lies on another candidate's fillet arc (between its tangent points, along the centreline) and the
  // surface points of its window inside that fillet's window (at least half of them, and circle_explained_min_points)
  // do not prefer its radius to the fillet's by a likelihood ratio of circle_explained_min_log_likelihood_ratio: the
  // fillet held at either radius, the rest of it fitted on those points (2 x cost difference / sigma^2). 4, two
  // standard errors: a tighter reading is dropped only where the surface does not support it even weakly. On a
  // spline the circle windows can read a curvature peak the constant-radius fillet averages away (S30 scene_006's
  // cable_B: 49.03 at its run's start for 43.27, the fillet over the peak 60.94, a ratio of 7.4: kept); a short kink
  // rejects a looser radius by far. Away from the runs' ends the rule did as much harm as good on the spline sets
  // (the surface tells a 55 mm window's 137 mm from 149 mm no better than by a ratio of 1.4, with the fillet's legs
  // free), and the circle figure stands. <= 0: off.
  double circle_explained_min_log_likelihood_ratio = 4.0;
  double circle_explained_end_diameters = 2.0;
  std::size_t circle_explained_min_points = 30;
  // The same for a circle figure anywhere along the run whose own fillet was refused for cutting the bend (its arc
  // goes on past a leg the window leaves unseen): the window is too short for the bend another candidate holds, and
  // its centreline figure, one of many windows over a long arc, is the one that read low (B40 scene_019's cable_B,
  // 5.5 mm: 53.07 +- 1.15 for an arc of 56.16 that two fillets read 56.25 +- 0.25 and 56.16 +- 0.48).
  bool circle_explained_cut = true;
  SmoothTubeFitParams smooth_fit;
};

// Optional access to the whole scan for the refit (see FilletRefineParams::regather); same frame as the points.
struct FilletScan {
  const Cloud* cloud = nullptr;
  const KdTree* tree = nullptr;
  const std::vector<std::uint8_t>* usable = nullptr;  // 0: not a cable point (e.g. on a rigid CAD surface)
  // The sensor's position (same frame), when known: the refits then keep only points on the side of the tube that
  // faces it and weigh them by the noise across the surface (FilletRefineParams::facing_min_cos, ray_noise_weights).
  bool has_sensor = false;
  Eigen::Vector3d sensor_position = Eigen::Vector3d::Zero();
};

// Whether the centreline samples with arc length strictly between a_mm and b_mm (`arc_mm`: each sample's) lie closer,
// in the sum of squares, to a fillet's circle continued past its tangent point `tangent` than to the line of its leg
// there (`leg`: unit, pointing away from the arc; `other_tangent`: the arc's other end, which fixes the side the
// circle bends to; `bend_radius_mm`: the circle's). True: the arc goes on where the fillet put a leg.
bool arc_goes_on_past_leg(const std::vector<Eigen::Vector3d>& centerline, const std::vector<double>& arc_mm,
                          double a_mm, double b_mm, const Eigen::Vector3d& tangent, const Eigen::Vector3d& leg,
                          const Eigen::Vector3d& other_tangent, double bend_radius_mm);

// Which legs of `m` part from the surface points `pts` (FilletRefineParams::leg_drift_*), as bits (1: leg1, 2: leg2):
// the points past a tangent point along its leg, within 3 `kernel_mm` of the surface, fitted around the leg's line
// moved by a + b t across it (t along the leg).
int fillet_leg_drifts(const FilletModel& m, const std::vector<Eigen::Vector3d>& pts, double kernel_mm,
                      const FilletRefineParams& params);

// A fillet fitted over a window of the centreline: where its arc and the window lie (arc lengths along the
// centreline, mm).
struct FittedArc {
  double arc_start_mm = 0.0, arc_end_mm = 0.0;        // the arc's tangent points (start <= end)
  double window_start_mm = 0.0, window_end_mm = 0.0;  // the window it was fitted over
  double radius_se_mm = 0.0;                          // the standard error of its bend radius
};

// Which fitted arcs their window cut (FilletRefineParams::cut_arcs_held_elsewhere): an arc ending less than
// `seen_mm` before an end of its window that is not an end of the run ([0, run_length_mm]), at a point strictly
// inside another arc whose window shows at least `seen_mm` of leg on both sides and whose radius is known at least as
// well (a window over a long arc's last stretch shows "legs" on the arc itself, and reads it less precisely than the
// whole arc's window, whose leg may be short). One flag per arc (1: cut).
std::vector<std::uint8_t> arcs_cut_by_their_windows(const std::vector<FittedArc>& arcs, double run_length_mm,
                                                    double seen_mm);

// Re-measures the tightest bends of `bend` (measure_bend_radius on `centerline`) with fillet fits to the cable's
// surface points, and replaces its minimum when a fit says the bend is tighter or looser than the circle
// windows did. `surface_points`: the cable's measured points (the set S of paper 4.3.2), same frame.
// Returns the number of bends re-measured. Deterministic.
int refine_bends_with_fillets(BendRadiusResult& bend, const std::vector<Eigen::Vector3d>& centerline,
                              const std::vector<Eigen::Vector3d>& surface_points, double tube_radius_mm,
                              double diameter_mm, const FilletRefineParams& params = {},
                              const FilletScan& scan = {});

}  // namespace ewis
