#pragma once
// Registration of a (filtered) scan to the CAD on its rigid elements (paper 4.1.2): from the initial pose when
// one is given (ICP with a shrinking correspondence distance), else globally (FPFH + RANSAC), then the final
// point-to-plane ICP with the cable exclusion zone re-evaluated at the refined pose.
#include <optional>

#include "ewis/register/cad_target.hpp"
#include "ewis/register/free_space.hpp"
#include "ewis/register/global_registration.hpp"
#include "ewis/register/icp.hpp"
#include "ewis/register/surface_refine.hpp"
#include "ewis/register/veil_points.hpp"
#include "ewis/register/weak_direction.hpp"

namespace ewis {

struct ScanToCadParams {
  IcpParams icp;                      // expected_error_mm: how far the initial pose may be off (default 60 mm)
  GlobalRegistrationParams global;
  double min_fitness = 0.3;           // below: the registration is not valid
  bool global_fallback = true;        // an initial pose whose ICP does not validate is retried globally
  // ... and so is one whose fitness stays below this (right poses on simulated scans: 0.945-0.998 over 140
  // scenes; a pose slid 47 mm along two parallel pipes: 0.83); the higher fitness wins
  double trusted_fitness = 0.9;
  // A background just beyond the CAD, within the crop's margin below (a floor 40 mm under the scene's plate and
  // boxes around it, bench/second_scanner.py), lowers a right pose's fitness too (0.81-0.95 on 30 such scenes, 28
  // of them under 0.9 and registered globally again: 4.3 s instead of 0.5). So a local result is trusted as well
  // when, over the scan points it maps into the CAD's bounding box grown by box_margin_mm, its fitness reaches
  // box_trusted_fitness and it puts at most box_trusted_in_front_fraction of the CAD's faces toward the sensor in
  // front of what was measured. The box alone is not enough: a pose slid along a symmetry maps its evidence against
  // itself out of the box (7 slid local results on the simulated sets: box fitness 0.87-0.93 but 6-17 % in front;
  // right poses behind those backgrounds: 0.98-1.00 and 0.1-1.6 %).
  double box_margin_mm = 10.0;
  double box_trusted_fitness = 0.95;
  double box_trusted_in_front_fraction = 0.03;
  // Where the box fitness over all those points falls short of box_trusted_fitness, it is measured again over the
  // ones on the scan's surfaces: a point whose 4th nearest neighbour in the scan (the whole scan the subsample was
  // drawn from) lies within box_surface_spacing_factor x the median of that distance over the box's points. The
  // radius outlier removal keeps, by design, the outliers within its radius of a surface (a structured-light
  // sensor's wrong depths a few mm along a ray); they fit no CAD face and lowered right poses' box fitness to
  // 0.86-0.95 (second scanner, 45 % outliers, 0.72 mm spacing: `ewis simulate --seed 7777 --campaign 30`, then
  // `bench/second_scanner.py --sigma-mm 0.25 --outliers 0.45 --focal-px 800 --mixed 0.8 --max-incidence-deg 70
  // --floor-z -30 --clutter 6`; 4 s a scene with the global search against 1.8). Of a right pose's box points
  // that fit, the median 4th-neighbour distance is 1.03 mm (90th percentile 1.38); of those that do not, 3.92 (10th
  // percentile 2.67). What contradicts a slid pose is a surface (an edge, a bracket), so it still counts.
  bool box_surface_only = true;
  double box_surface_spacing_factor = 2.0;
  // ... and, with the sensor's viewpoint known (icp.use_source_viewpoint), only where the rays next to the point's own
  // hold at least box_surface_min_same other points at its range (filter/ray_neighbours.hpp; rays within 1.5 x the
  // box points' median nearest-neighbour distance, ranges within 0.6 mm): a surface goes on there, a wrong range does
  // not. Another simulator's outliers (40 % of the pixels off by a Gaussian 1.5-3 mm along the ray,
  // bench/depth_noise.py) lie near the surfaces, pass the spacing test, fit no CAD face, and lowered right poses' box
  // fitness under box_trusted_fitness: such scenes were registered again globally (4.5-5.4 s a scene instead of 1.3).
  // 0: the spacing test alone.
  std::size_t box_surface_min_same = 2;
  int global_candidates = 3;          // best global candidates refined at full resolution; highest fitness wins
  // A global candidate whose refinement is not trusted (fitness under trusted_fitness or more CAD in front than
  // trusted_in_front_fraction; not one stopped after its coarse pass as beaten) is refined again with the zones
  // around the cables not grown by its uncertainty (the higher support wins): grown by 2 voxels (20 mm), they took in
  // the clamps and connectors that held the pose along a plate (fresh campaign `--seed 2468 --campaign 40 --cables 3 --mismatch-patches 150 --outliers 0.45 --noise-mm
  // 0.25`, scene_010 without its pose: a start 3.3 mm from the truth slid 14.3 mm along the plate, fitness 0.88 and
  // 4.3 % in front; ungrown, 0.01 mm).
  bool global_refine_ungrown = true;
  // A result from the initial pose that is not trusted (the tests above) is refined again from that pose with the
  // zones around the cables grown in the coarse pass by the whole expected error instead of at most 20 mm (the
  // higher support wins; before the global search, which it spares when the result is then trusted). Seen from
  // the side (`ewis plan`'s covering views, the sensor level with the plate), the cables fill most of the view
  // and, from a start 30 mm off, lie outside 20 mm zones: the coarse pass matched them onto the plate and
  // connectors (bench/planned_views.py, seed 1357: 6 of 40 side views 80-130 mm off, fitness 0.45-0.57).
  bool local_retry_grown_full = true;
  // Before that, an untrusted result from the initial pose is refined again as if the pose were at most this far off
  // (mm; the coarse pass then reaches 3 x as far instead of 3 x icp.expected_error_mm; 0: not tried). Boxes beside
  // the CAD inside the crop's margin (the second scanner's clutter level with the plate) pulled the 180 mm
  // correspondences of starts 2-3 deg and 2-12 mm off by 1.5 deg to 260 mm (1 scene in 30 of two fresh sets; the
  // global search found the pose, 10 s a scene). Kept only when trusted with at most box_trusted_in_front_fraction of
  // the CAD in front and the higher support: a near retry slid 36.8 mm along a plate scored fitness 0.96 with 5.0 %
  // in front, which trusted_in_front_fraction alone would let pass (the grown retry then finds the pose).
  double local_retry_near_mm = 20.0;
  // A result from the initial pose that is not trusted is refined again from that pose with the coarse pass matched
  // to the cables' CAD samples as well as the rigid ones, over every point (no zones; the fine pass is as always, on
  // the rigid elements alone with the zones at the coarse pose); the higher support wins, before the retries below. A
  // cable lies where its CAD says within millimetres, which the fine pass's reach absorbs, and it fixes what a view
  // filled by a plate leaves loose: the slide along the plate and the turn about its normal (C's scene_016 cut to the
  // middle of the image, a plate, a small bracket, clamps and two cables: refined 30 mm off, fitness 0.87, then turned
  // upside down by the global search; 0.14 deg / 0.95 mm with the cables). Not done to every refinement: the coarse
  // pass over every point and its own view of the CAD cost the demo's registration 0.20 s more (docs/register.md).
  bool local_retry_on_cables = true;
  // After each fine pass: the fitness probed along the weakest direction of translation (weak_direction.hpp).
  WeakDirectionParams weak_direction;
  // Speed: every step runs on an evenly strided subsample of the scan of at most this many points (0: all).
  // Six unknowns: 5 x 10^4 well-spread points pin the pose far below the noise; fitness and rmse are measured
  // on the same subsample (an unbiased estimate of the whole scan's).
  std::size_t max_scan_points = 50000;
  std::size_t rank_probe_points = 2000;  // subsample points that re-rank the global candidates
  // With icp.use_source_viewpoint (the scan in its sensor's frame): veils of mixed pixels are dropped from the
  // subsample before anything else (veil_points.hpp); they bias the pose along weakly constrained directions.
  bool drop_veils = true;
  // Scan points the initial pose maps farther than icp.expected_error_mm outside the CAD's bounding box are left
  // out when they are a background the CAD does not model (>= 5 % of the scan); without an initial pose, the
  // same is done with the global search's pose and the registration repeated from it.
  bool crop_to_cad = true;
  VeilParams veil;
  // Free space (free_space.hpp; with icp.use_source_viewpoint): of the CAD's faces toward the sensor, the fraction
  // a pose puts nearer than everything the sensor measured along their rays (by more than in_front_margin_mm)
  // discounts its fitness: poses compete on fitness x (1 - fraction). Right poses: 0-1.4 %; the floor matched
  // onto a plate: 35 %; a pipe missing from the scan at the right pose: 19 %. A local result above
  // trusted_in_front_fraction is checked by the global search too; above max_in_front_fraction a pose is not valid.
  bool check_free_space = true;
  double trusted_in_front_fraction = 0.1;
  double max_in_front_fraction = 0.5;
  double in_front_margin_mm = 10.0;
  // The last step on the CAD's exact surface (surface_refine.hpp), when the target indexes it: the valid result
  // is refined on the same points its final ICP used. Its distances: the final ICP's.
  bool refine_on_surface = true;
  SurfaceRefineParams surface;
  // The scan is in its sensor's frame (CONTRACT: scan.ply), so CAD faces turned away from the sensor are culled.
  ScanToCadParams() {
    icp.expected_error_mm = 60.0;
    icp.use_source_viewpoint = true;
    icp.coarse_max_points = 5000;  // coarse stages only hand over a pose within a few mm
    icp.max_points = 30000;
    global.try_all_scales = true;  // candidates of every scale are re-ranked at full resolution
  }
};

struct ScanToCadResult {
  RegistrationResult registration;    // source_to_target = scan_to_cad; fitness over the points used (the
                                      // subsample without veils and without the cable exclusion zone)
  bool valid = false;                 // fitness >= min_fitness, in-front fraction <= max_in_front_fraction
  bool used_global = false;
  std::size_t excluded_near_cables = 0;  // scan points left out as lying on a cable's CAD position
  FreeSpaceCount free_space;          // the CAD's faces toward the sensor, and those in front of the scan
  // The fitness over the points the pose maps into the CAD's box grown by box_margin_mm (from the initial pose: over
  // those on the scan's surfaces where that falls short, see box_surface_only); measured where the fitness is under
  // trusted_fitness, else 0.
  double box_fitness = 0.0;
};

// The box rule (ScanToCadParams::box_*): a background the CAD lacks explains a fitness under trusted_fitness, since
// inside the CAD's box the pose fits (`box_fitness`) and puts at most box_trusted_in_front_fraction of the CAD in
// front of the scan.
bool background_explains_fitness(double box_fitness, double in_front_fraction, const ScanToCadParams& params);

// `scan` in scan coordinates (mm, already filtered). Deterministic for any thread count.
ScanToCadResult register_scan_to_cad(const Cloud& scan, const CadTarget& target,
                                     const std::optional<Pose>& initial_scan_to_cad,
                                     const ScanToCadParams& params = {}, const ProgressFn& progress = {});

}  // namespace ewis
