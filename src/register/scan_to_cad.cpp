// Scan-to-CAD registration on the rigid elements (paper 4.1.2, 4.2): ICP from the initial pose (or from the
// global registration's pose), in two passes: a coarse pass with the cable exclusion zone widened by the pose
// uncertainty, then a fine pass with the zone re-evaluated at the refined pose.
//
// Speed (issue 4): a pose has six unknowns, so a well-spread subsample of the scan (tens of thousands of points)
// pins it far below the sensor noise; every step (exclusion zone, ICP, fitness) runs on that subsample. Each pass
// matches against the part of the CAD target that faces the sensor and lies within the pass's correspondence
// distance of the scan: a small k-d tree, built once per pass.
//
// Mixed pixels (issue: a plate scene converged 15 mm off): when the scan is in its sensor's frame, the veils of
// mixed pixels at depth edges are dropped from the subsample first (veil_points.hpp). A veil hangs ~1 mm beside
// the CAD face behind its edge and, matched to it, drags the pose along the directions a large plate leaves
// weak; the robust kernel cannot tell it from a real face at that distance, and it counts as fitness too.
#include "ewis/register/scan_to_cad.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "ewis/core/error.hpp"
#include "ewis/core/parallel.hpp"
#include "ewis/filter/ray_neighbours.hpp"
#include "ewis/register/free_space.hpp"
#include "ewis/register/veil_points.hpp"
#include "ewis/search/spatial_sort.hpp"

namespace ewis {
namespace {

struct Run {
  RegistrationResult reg;
  std::size_t excluded = 0;  // of the subsample
  FreeSpaceCount free_space;  // the CAD's faces toward the sensor that lie in front of what it measured
  double box_fitness = 0.0;  // over the points the pose maps into the CAD's box; 0: not measured (see refine)
  bool beaten = false;       // stopped after its coarse pass: it could not win (see refine's beaten_below)
};

// The whole scan a subsample was drawn from, with its k-d tree built on first use (ScanToCadParams::box_surface_only):
// which of the subsample's points lie on the scan's surfaces.
struct ScanSurfaces {
  const std::vector<Eigen::Vector3f>* all = nullptr;
  std::unique_ptr<KdTree> tree;
};

// The fitness over the points of `inside` (subsample indices) on the scan's surfaces: a point's 4th nearest neighbour
// in the whole scan within spacing_factor x the median of that distance over `inside` (the point itself, in the
// scan too, is its own nearest), and with a viewpoint, at least min_same other points at its range on the rays next to
// its own (ScanToCadParams::box_surface_min_same). -1: not measurable (too few points).
double fitness_on_surfaces(const std::vector<Eigen::Vector3f>& scan, const std::vector<std::uint32_t>& inside,
                           ScanSurfaces& surfaces, const Cloud& target, const KdTree& target_tree, const Pose& pose,
                           double inlier_distance_mm, double spacing_factor, const Eigen::Vector3d* viewpoint,
                           std::size_t min_same) {
  constexpr int kNeighbours = 5;  // itself and 4 others
  if (!surfaces.all || surfaces.all->size() < kNeighbours || inside.empty()) return -1.0;
  if (!surfaces.tree) surfaces.tree = std::make_unique<KdTree>(*surfaces.all);
  const KdTree& tree = *surfaces.tree;
  std::vector<float> spacing(inside.size()), nearest(inside.size());
  parallel_blocks(inside.size(), 1024, [&](std::size_t begin, std::size_t end) {
    std::vector<Neighbor> nn;
    for (std::size_t j = begin; j < end; ++j) {
      tree.knn(scan[inside[j]], kNeighbours, nn);
      const bool full = nn.size() == kNeighbours;
      spacing[j] = full ? std::sqrt(nn.back().distance_sq) : std::numeric_limits<float>::infinity();
      nearest[j] = full ? std::sqrt(nn[1].distance_sq) : std::numeric_limits<float>::infinity();
    }
  });
  const auto median = [](std::vector<float> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return double(v[v.size() / 2]);
  };
  const double limit = spacing_factor * median(spacing);
  std::vector<std::uint8_t> on_surface(inside.size(), 0);
  const bool by_rays = viewpoint && min_same > 0;
  RayNeighbourParams rp;
  if (by_rays) rp.lateral_mm = 1.5 * median(nearest);
  parallel_blocks(inside.size(), 1024, [&](std::size_t begin, std::size_t end) {
    std::vector<Neighbor> scratch;
    for (std::size_t j = begin; j < end; ++j) {
      if (!(spacing[j] <= limit)) continue;
      // the point is in the whole scan too: it counts at its own range
      on_surface[j] = !by_rays || ray_neighbours(tree, ~0u, scan[inside[j]].cast<double>(), *viewpoint, rp, scratch)
                                          .same >= min_same + 1;
    }
  });
  std::vector<std::uint32_t> on;
  on.reserve(inside.size());
  for (std::size_t j = 0; j < inside.size(); ++j)
    if (on_surface[j]) on.push_back(inside[j]);
  if (on.empty()) return -1.0;
  return evaluate_registration(scan, target, target_tree, pose, inlier_distance_mm, on).fitness;
}

// How well the scan supports a pose: its fitness, discounted by the fraction of the CAD's seen faces it puts in
// front of what the sensor measured (free_space.hpp). Soft, not a veto: a part of the CAD missing from the
// assembly is in front of what was measured at the right pose too (a pipe missing from a small scene: 19 %; a
// veto sent that scene to a pose 33 mm off that hid the pipe outside the view, fitness 0.59 against 1.00).
double support(const RegistrationResult& reg, const FreeSpaceCount& c) { return reg.fitness * (1.0 - c.fraction()); }

// The CAD samples a pass may match: facing the sensor (when the scan is in its sensor's frame: a scanned plate's
// top must not lock onto the CAD plate's bottom face) and inside the box of the scan at `pose` grown by
// `margin_mm` (nothing farther can be a correspondence); the rigid elements', with `with_cables` the cables' too.
// Owns its k-d tree.
struct TargetView {
  std::unique_ptr<Cloud> cloud;  // held apart: the tree refers to its points, which a move of the view must not move
  std::unique_ptr<KdTree> tree;
};

TargetView view_of(const CadTarget& target, const std::vector<Eigen::Vector3f>& source, const Pose& pose,
                   bool cull_back_faces, const Eigen::Vector3d& viewpoint, double margin_mm, bool with_cables = false) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = Eigen::Vector3d::Constant(-1e300);
  for (const auto& p : source) {
    const Eigen::Vector3d q = pose * p.cast<double>();
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  const Eigen::Vector3f blo = (lo.array() - margin_mm).cast<float>(), bhi = (hi.array() + margin_mm).cast<float>();
  const Eigen::Vector3d eye = pose * viewpoint;
  TargetView v;
  v.cloud = std::make_unique<Cloud>(sample_rigid_view(target, blo, bhi, cull_back_faces ? &eye : nullptr));
  if (with_cables) {  // the cables' samples after the rigid ones
    const Cloud c = sample_cable_view(target, blo, bhi, cull_back_faces ? &eye : nullptr);
    v.cloud->points.insert(v.cloud->points.end(), c.points.begin(), c.points.end());
    v.cloud->normals.insert(v.cloud->normals.end(), c.normals.begin(), c.normals.end());
  }
  // In its leaf order, with the tree the sort built: the tree uses the points in place (issue 8: peak memory).
  v.tree = std::make_unique<KdTree>(sort_for_search(*v.cloud));
  return v;
}

// Scan points beyond the CAD's box (grown by the pose error) are left out of the registration when they are
// at least this fraction of the scan (see register_scan_to_cad).
constexpr double kMinBackgroundFraction = 0.05;

// The CAD's bounding box (every element, cables included).
Eigen::AlignedBox3d cad_box(const CadTarget& target) {
  Eigen::AlignedBox3d box;
  if (target.scene) {
    for (const Element& e : target.scene->elements) {
      box.extend(e.bounds_min);
      box.extend(e.bounds_max);
    }
  }
  for (const Eigen::Vector3f& p : target.rigid.points) box.extend(p.cast<double>());
  for (const Eigen::Vector3f& p : target.cables.points) box.extend(p.cast<double>());
  return box;
}

// Whether `pose` maps a scan point into the CAD's box grown by `grow_mm`.
struct CadReach {
  Eigen::AlignedBox3f box;
  Eigen::Matrix3f R;
  Eigen::Vector3f t;
  bool operator()(const Eigen::Vector3f& p) const { return box.contains(R * p + t); }
};

CadReach cad_reach(const CadTarget& target, const Pose& pose, double grow_mm) {
  const Eigen::AlignedBox3d box = cad_box(target);
  const Eigen::Vector3d grow = Eigen::Vector3d::Constant(grow_mm);
  return {Eigen::AlignedBox3d(box.min() - grow, box.max() + grow).cast<float>(), pose.linear().cast<float>(),
          pose.translation().cast<float>()};
}

// The final correspondence distance: ~1 mm, but never below what the sampling spacing and the noise need.
double final_distance_mm(const IcpParams& icp, const CadTarget& target) {
  return std::max(icp.final_max_distance_mm, target.spacing_mm + 3.0 * icp.noise_mm);
}

// The zones around the cables grow by a start's uncertainty at most this much in the coarse pass (see refine).
constexpr double kZoneGrowCapMm = 20.0;

// `beaten_below`: the support of the best pose refined so far (0: none). A start whose coarse pass ends with a fitness
// under it is not refined further: the fine pass measures the fitness at a third of the coarse pass's distance, and
// the support discounts it again, so it cannot win (a wrong global start of the demo ran 70 fine iterations, 0.18 s,
// to 0.58 against the right start's 0.98).
// `grow_cap_mm`: the zones around the cables grow in the coarse pass by the start's uncertainty, at most this much
// (0: not grown; see below).
// `cables`: the coarse pass matches the cables' CAD too, over every point (ScanToCadParams::local_retry_on_cables).
Run refine(const std::vector<Eigen::Vector3f>& scan, const CadTarget& target, const Pose& start,
           double expected_error_mm, const ScanToCadParams& params, const ProgressFn& progress,
           const RangeBins* bins, double beaten_below = 0.0, double grow_cap_mm = kZoneGrowCapMm,
           ScanSurfaces* surfaces = nullptr, bool cables = false) {
  IcpParams icp = params.icp;
  const double final_d = final_distance_mm(icp, target);
  icp.final_max_distance_mm = final_d;
  icp.expected_error_mm = expected_error_mm;
  const bool cull = icp.use_source_viewpoint;
  icp.use_source_viewpoint = false;  // done here, once per pass, on the cropped target

  // While the pose is uncertain, the zone around each cable grows by that uncertainty (bounded, so that a
  // scene with many cables keeps enough rigid points).
  const bool on_cables = cables && target.cable_tree && target.cables.has_normals();
  std::vector<std::uint32_t> keep =
      on_cables ? parallel_select(scan.size(), [](std::size_t) { return true; })
                : points_away_from_cables(scan, start, target, std::min(expected_error_mm, grow_cap_mm));
  if (keep.size() < std::max<std::size_t>(50, scan.size() / 10)) keep = points_away_from_cables(scan, start, target, 0.0);
  Run run;
  if (keep.size() < 6) return run;
  const double coarse_reach = icp.initial_max_distance_mm > 0 ? icp.initial_max_distance_mm
                                                              : std::max(3.0 * icp.expected_error_mm, 10.0);
  // One view of the CAD for both passes: the pose changes by at most the expected error (~10 deg) in between,
  // less than the culling test's slack, and the crop margin covers the coarse pass's largest distance.
  const TargetView view =
      view_of(target, scan, start, cull, params.icp.source_viewpoint, std::max(coarse_reach, final_d) + 1.0);
  if (view.cloud->size() < 3) return run;
  // The coarse pass hands over a pose well inside the fine pass's first distance; the fine pass (with the
  // exclusion zone at the refined pose) takes it down to the final distance.
  IcpParams coarse_icp = icp;
  coarse_icp.final_max_distance_mm = std::max(3.0 * final_d, 4.0);
  coarse_icp.coarse_distance_mm = 4.0 * final_d;
  IcpMemory memory;  // the fine pass goes on from the coarse pass's correspondences (on the same view)
  TargetView with_cables;
  if (on_cables)
    with_cables = view_of(target, scan, start, cull, params.icp.source_viewpoint, std::max(coarse_reach, final_d) + 1.0,
                          true);
  const TargetView& coarse_view = on_cables ? with_cables : view;
  IcpMemory coarse_memory;
  const RegistrationResult coarse = align_point_to_plane(scan, *coarse_view.cloud, *coarse_view.tree, start, coarse_icp,
                                                         keep, progress, on_cables ? &coarse_memory : &memory);
  with_cables = TargetView{};
  if (coarse.fitness < beaten_below) {
    run.beaten = true;
    run.reg = coarse;
    run.excluded = scan.size() - keep.size();
    return run;
  }
  keep = points_away_from_cables(scan, coarse.source_to_target, target, 0.0);
  if (keep.size() < 6) return run;
  IcpParams fine = icp;
  fine.initial_max_distance_mm = coarse_icp.final_max_distance_mm;
  run.reg = align_point_to_plane(scan, *view.cloud, *view.tree, coarse.source_to_target, fine, keep, {}, &memory);
  run.reg.iterations += coarse.iterations;
  // A pose the scene hardly fixes along one direction (weak_direction.hpp): the fitness probed along it, and the fine
  // pass run again from where it rises most; the higher fitness stays.
  // Again while the fitness rises (a pose far off along the plate climbs params.weak_direction.reach_mm a round).
  for (int round = 0; params.weak_direction.enabled && round < params.weak_direction.max_rounds; ++round) {
    const std::vector<std::uint32_t> probe = pick(keep, evenly_strided(keep.size(), params.weak_direction.probe_points));
    const WeakDirection weak = weakest_translation(scan, probe, *view.cloud, *view.tree, run.reg.source_to_target,
                                                   run.reg.inlier_distance_mm);
    if (weak.ratio >= params.weak_direction.max_ratio) break;
    const double offset = best_offset_along(scan, probe, *view.cloud, *view.tree, run.reg.source_to_target,
                                            weak.direction, run.reg.inlier_distance_mm, params.weak_direction);
    if (offset == 0.0) break;
    Pose moved = run.reg.source_to_target;
    moved.translation() += offset * weak.direction;
    std::vector<std::uint32_t> moved_keep = points_away_from_cables(scan, moved, target, 0.0);
    if (moved_keep.size() < 6) break;
    RegistrationResult again = align_point_to_plane(scan, *view.cloud, *view.tree, moved, fine, moved_keep);
    if (!(again.fitness > run.reg.fitness)) break;
    again.iterations += run.reg.iterations;
    run.reg = again;
    keep = std::move(moved_keep);
  }
  run.excluded = scan.size() - keep.size();
  // Where the fitness alone would not trust the pose: the fitness over the points it maps into the CAD's box grown by
  // box_margin_mm (ScanToCadParams::box_*), which a background just beyond the CAD (a panel 40 mm under the scene's
  // plate, boxes beside it), within the crop's margin of the pose's uncertainty, does not lower.
  if (run.reg.fitness < params.trusted_fitness) {
    const CadReach reach = cad_reach(target, run.reg.source_to_target, params.box_margin_mm);
    std::vector<std::uint32_t> inside;
    inside.reserve(keep.size());
    for (std::uint32_t i : keep)
      if (reach(scan[i])) inside.push_back(i);
    if (!inside.empty())
      run.box_fitness = evaluate_registration(scan, *view.cloud, *view.tree, run.reg.source_to_target,
                                              run.reg.inlier_distance_mm, inside)
                            .fitness;
    if (surfaces && params.box_surface_only && run.box_fitness < params.box_trusted_fitness) {
      const double on = fitness_on_surfaces(scan, inside, *surfaces, *view.cloud, *view.tree, run.reg.source_to_target,
                                            run.reg.inlier_distance_mm, params.box_surface_spacing_factor,
                                            cull ? &params.icp.source_viewpoint : nullptr, params.box_surface_min_same);
      if (on >= 0.0) run.box_fitness = on;
    }
  }
  if (bins) run.free_space = count_in_front(*bins, *view.cloud, run.reg.source_to_target, params.in_front_margin_mm);
  return run;
}

// What `pose` maps farther than `grow_mm` outside the CAD's box cannot be on the CAD: a floor, the robot cell,
// the rest of the aircraft. Returns the scan without it when it is a background: at least kMinBackgroundFraction
// of the scan (after outlier removal a scan of the scene alone has ~0.03 % there, and dropping those only
// redraws the subsample: on the 140-scene campaign that moved 3 registrations past 0.3 mm, both ways), and not so
// much that under a tenth would remain (the pose is then far off; the global search needs all). Else empty.
std::vector<Eigen::Vector3f> without_background(const std::vector<Eigen::Vector3f>& scan, const CadTarget& target,
                                                const Pose& pose, double grow_mm) {
  std::vector<Eigen::Vector3f> cropped;
  if (scan.empty()) return cropped;
  const CadReach reach = cad_reach(target, pose, grow_mm);
  std::size_t inside = 0;
  for (const Eigen::Vector3f& p : scan) inside += reach(p);
  const double outside = 1.0 - static_cast<double>(inside) / static_cast<double>(scan.size());
  if (inside >= scan.size() / 10 && outside >= kMinBackgroundFraction) {
    cropped.reserve(inside);
    for (const Eigen::Vector3f& p : scan)
      if (reach(p)) cropped.push_back(p);
  }
  return cropped;
}

// `scan_per_point`: scan points each subsample point stands for (to report counts for the whole scan).
ScanToCadResult register_subsample(const std::vector<Eigen::Vector3f>& scan, double scan_per_point,
                                   const CadTarget& target, const std::optional<Pose>& initial_scan_to_cad,
                                   const ScanToCadParams& params, const ProgressFn& progress, const RangeBins* bins,
                                   const std::vector<Eigen::Vector3f>* all) {
  ScanToCadResult res;
  ScanSurfaces surfaces{all, nullptr};  // for the local results' box fitness
  bool have = false;
  // The higher support wins.
  auto consider = [&](const Run& r, bool global) {
    if (r.reg.inliers == 0 && have) return;
    if (!have || support(r.reg, r.free_space) > support(res.registration, res.free_space)) {
      res.registration = r.reg;
      res.excluded_near_cables = r.excluded;
      res.used_global = global;
      res.free_space = r.free_space;
      res.box_fitness = r.box_fitness;
      have = true;
    }
  };
  // A pose slid along a symmetry of the scene (parallel pipes, a plate's long edge) still validates, but with a
  // fitness well below a right pose's: below trusted_fitness (or above trusted_in_front_fraction) the global
  // registration is tried too, and the higher support wins; unless a background explains the fitness: inside the
  // CAD's box the pose fits as right poses do, and it puts hardly any CAD face in front of what was measured
  // (ScanToCadParams::box_*).
  auto fits_as_initial = [&](const Run& r) {
    const double in_front = r.free_space.fraction();
    const bool fits =
        r.reg.fitness >= params.trusted_fitness || background_explains_fitness(r.box_fitness, in_front, params);
    return r.reg.inliers > 0 && r.reg.fitness >= params.min_fitness && fits &&
           in_front <= params.trusted_in_front_fraction;
  };
  bool ok = false;
  if (initial_scan_to_cad) {
    const Run local = refine(scan, target, *initial_scan_to_cad, params.icp.expected_error_mm, params, progress, bins,
                             0.0, kZoneGrowCapMm, &surfaces);
    consider(local, false);
    ok = fits_as_initial(local);
    // (ScanToCadParams::local_retry_on_cables)
    if (!ok && params.local_retry_on_cables && target.cable_tree) {
      const Run anchored = refine(scan, target, *initial_scan_to_cad, params.icp.expected_error_mm, params, progress,
                                  bins, 0.0, kZoneGrowCapMm, &surfaces, true);
      if (support(anchored.reg, anchored.free_space) > support(res.registration, res.free_space)) {
        consider(anchored, false);
        ok = fits_as_initial(anchored);
      }
    }
    // (ScanToCadParams::local_retry_near_mm): kept only under the box rule's bound on the CAD in front. Tried too
    // where a trusted result puts more of the CAD in front than that bound (right poses: 0-1.9 %): slid along a plate.
    const bool slid = ok && res.free_space.fraction() > params.box_trusted_in_front_fraction;
    if ((!ok || slid) && params.local_retry_near_mm > 0.0 && params.icp.expected_error_mm > params.local_retry_near_mm) {
      const Run near = refine(scan, target, *initial_scan_to_cad, params.local_retry_near_mm, params, progress, bins,
                              0.0, kZoneGrowCapMm, &surfaces);
      if (fits_as_initial(near) && near.free_space.fraction() <= params.box_trusted_in_front_fraction &&
          support(near.reg, near.free_space) > support(res.registration, res.free_space)) {
        consider(near, false);
        ok = true;
      }
    }
    // (ScanToCadParams::local_retry_grown_full)
    if (!ok && params.local_retry_grown_full && params.icp.expected_error_mm > kZoneGrowCapMm) {
      const Run wide = refine(scan, target, *initial_scan_to_cad, params.icp.expected_error_mm, params, progress, bins,
                              support(res.registration, res.free_space), params.icp.expected_error_mm, &surfaces);
      if (!wide.beaten && support(wide.reg, wide.free_space) > support(res.registration, res.free_space)) {
        consider(wide, false);
        ok = fits_as_initial(wide);
      }
    }
  }
  if (!initial_scan_to_cad || (!ok && params.global_fallback)) {
    // The candidates to refine, best first; everything the search needed is freed before the refinement
    // (each refinement draws its own view of the CAD).
    std::vector<Pose> starts;
    double voxel_mm = 0.0;
    {
      Cloud source;
      source.points = scan;
      // Every rigid sample (drawn now when the target samples per view).
      Cloud drawn;
      if (target.rigid.empty()) {
        drawn = sample_rigid_all(target);
        sort_for_search(drawn);  // the rigid tree below then makes no copy (issue 8: peak memory)
      }
      const Cloud& all = target.rigid.empty() ? drawn : target.rigid;
      const GlobalRegistrationResult g = register_global(source, all, params.global, progress);
      voxel_mm = g.voxel_mm;
      // Symmetric parts of a scene (a plate, rows of blocks) give near-ties at the coarse scale: re-rank all the
      // candidates by their fitness on the full-resolution target at a tighter distance, then the full ICP of
      // the first few decides.
      std::vector<std::uint32_t> probe;
      const std::size_t stride =
          std::max<std::size_t>(1, scan.size() / std::max<std::size_t>(params.rank_probe_points, 1));
      for (std::size_t i = 0; i < scan.size(); i += stride) probe.push_back(static_cast<std::uint32_t>(i));
      // ... by their support, with the free space counted at the search's precision (a margin of 2 voxels).
      const double tight = std::max(0.4 * g.voxel_mm, 3.0);
      std::vector<std::pair<double, std::size_t>> ranked;
      const KdTree rigid_tree(all.points);
      const double coarse_margin = std::max(params.in_front_margin_mm, 2.0 * g.voxel_mm);
      for (std::size_t i = 0; i < g.candidates.size(); ++i) {
        const Pose& T = g.candidates[i].source_to_target;
        const FreeSpaceCount seen = bins ? count_in_front(*bins, all, T, coarse_margin) : FreeSpaceCount{};
        ranked.emplace_back(support(evaluate_registration(scan, all, rigid_tree, T, tight, probe), seen), i);
      }
      std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
      // Distinct starts: candidates of different scales often converged to the same pose, and three refinements
      // of one wrong pose left the right one, ranked fourth, unrefined (a floor-and-boxes scene).
      const std::size_t n = static_cast<std::size_t>(std::max(1, params.global_candidates));
      for (std::size_t k = 0; k < ranked.size() && starts.size() < n; ++k) {
        const Pose& T = g.candidates[ranked[k].second].source_to_target;
        const bool repeated = std::any_of(starts.begin(), starts.end(), [&](const Pose& S) {
          return rotation_error_deg(S, T) < 2.0 && translation_error_mm(S, T) < 2.0 * g.voxel_mm;
        });
        if (!repeated) starts.push_back(T);
      }
    }
    // Each refined without the background its start shows, as an initial pose is (beyond the CAD's box grown
    // by icp.expected_error_mm: a tighter box also drops the points that speak against a wrong start, and a
    // small scene's plate seen from behind, its cable's points cropped, fitted perfectly): a floor-and-boxes
    // scene's right start slid 190 mm along the plate, pulled by the boxes beside it.
    const double expected_mm = std::max(2.0 * voxel_mm, 5.0);
    for (const Pose& start : starts) {
      const std::vector<Eigen::Vector3f> cropped =
          params.crop_to_cad ? without_background(scan, target, start, params.icp.expected_error_mm)
                             : std::vector<Eigen::Vector3f>{};
      const std::vector<Eigen::Vector3f>& points = cropped.empty() ? scan : cropped;
      const Run grown = refine(points, target, start, expected_mm, params, progress, bins,
                               have ? support(res.registration, res.free_space) : 0.0);
      consider(grown, true);
      // (ScanToCadParams::global_refine_ungrown)
      const bool trusted = grown.reg.fitness >= params.trusted_fitness &&
                           grown.free_space.fraction() <= params.trusted_in_front_fraction;
      if (params.global_refine_ungrown && !trusted && !grown.beaten)
        consider(refine(points, target, start, expected_mm, params, progress, bins,
                        have ? support(res.registration, res.free_space) : 0.0, 0.0),
                 true);
    }
  }
  res.valid = have && res.registration.fitness >= params.min_fitness &&
              res.free_space.fraction() <= params.max_in_front_fraction;
  if (res.valid && params.refine_on_surface && target.surface) {
    // The last step on the exact surface, on the points the final ICP used (the fitness stays the ICP's).
    const std::vector<std::uint32_t> keep =
        points_away_from_cables(scan, res.registration.source_to_target, target, 0.0);
    SurfaceRefineParams sp = params.surface;
    sp.max_distance_mm = final_distance_mm(params.icp, target);
    sp.kernel_mm = icp_kernel_scale_mm(params.icp, sp.max_distance_mm);
    if (keep.size() >= 6)
      res.registration.source_to_target =
          refine_on_surface(scan, *target.surface, res.registration.source_to_target, sp, keep).source_to_target;
  }
  // The count of left-out points is reported for the whole scan (the subsample is an even spread of it).
  res.excluded_near_cables =
      static_cast<std::size_t>(std::llround(static_cast<double>(res.excluded_near_cables) * scan_per_point));
  return res;
}

ScanToCadResult register_points(const std::vector<Eigen::Vector3f>& all, const CadTarget& target,
                                const std::optional<Pose>& initial_scan_to_cad, const ScanToCadParams& params,
                                const ProgressFn& progress, const RangeBins* bins) {
  // An even spread over the image (the scan is in raster order)
  const std::vector<Eigen::Vector3f> sub = pick(all, evenly_strided(all.size(), params.max_scan_points));
  const double per_point = static_cast<double>(all.size()) / static_cast<double>(sub.size());
  if (!params.icp.use_source_viewpoint)
    return register_subsample(sub, per_point, target, initial_scan_to_cad, params, progress, nullptr, &all);

  // In the sensor's frame: without the veils of mixed pixels (unless nearly everything looks like one: then
  // the scan is not in its sensor's frame after all, and the retry below uses every point).
  std::vector<Eigen::Vector3f> clean;
  if (params.drop_veils) {
    const std::vector<std::uint32_t> off = points_off_veils(sub, params.icp.source_viewpoint, params.veil);
    if (off.size() >= sub.size() / 2) clean = pick(sub, off);
  }
  const std::vector<Eigen::Vector3f>& used = clean.empty() ? sub : clean;
  ScanToCadResult res = register_subsample(used, per_point, target, initial_scan_to_cad, params, progress, bins, &all);
  if (!res.valid) {
    // The scan may not be in its sensor's frame after all: retry once without visibility culling or veils.
    ScanToCadParams plain = params;
    plain.icp.use_source_viewpoint = false;
    ScanToCadResult retry =
        register_subsample(sub, per_point, target, initial_scan_to_cad, plain, progress, bins, &all);
    const bool better = retry.registration.fitness > res.registration.fitness;
    if ((retry.valid && !res.valid) || (retry.valid == res.valid && better)) res = retry;
  }
  return res;
}

}  // namespace

bool background_explains_fitness(double box_fitness, double in_front_fraction, const ScanToCadParams& params) {
  return box_fitness >= params.box_trusted_fitness && in_front_fraction <= params.box_trusted_in_front_fraction;
}

ScanToCadResult register_scan_to_cad(const Cloud& scan, const CadTarget& target,
                                     const std::optional<Pose>& initial_scan_to_cad, const ScanToCadParams& params,
                                     const ProgressFn& progress) {
  if (scan.empty()) throw InputError("", "registration: the scan has no points");
  if (!has_rigid(target)) throw InputError("", "registration: empty CAD target");
  // A background (see without_background) pulls the ICP (a floor 150 mm under the scene's plate held 6 mm and
  // 1 deg of error) and outvotes the scene in the fitness by which a global candidate is preferred and a pose
  // validated (that floor, matched onto the plate: 190 mm off). With an initial pose it is left out before the
  // subsample is drawn (so that holds as many scene points as before). The sensor's range image is binned from
  // the whole scan (the background included: it is seen free space too).
  const RangeBins bins = params.icp.use_source_viewpoint && params.check_free_space
                             ? bin_scan_depths(scan.points)
                             : RangeBins{};
  const RangeBins* seen = bins.bin > 0 ? &bins : nullptr;
  if (initial_scan_to_cad) {
    const std::vector<Eigen::Vector3f> cropped =
        params.crop_to_cad ? without_background(scan.points, target, *initial_scan_to_cad, params.icp.expected_error_mm)
                           : std::vector<Eigen::Vector3f>{};
    return register_points(cropped.empty() ? scan.points : cropped, target, initial_scan_to_cad, params, progress,
                           seen);
  }
  // Without one, the global search finds the pose on the whole scan; where that pose shows a background, the
  // registration is done again from it without the background (the fitness that validates it then counts the
  // scene's points only: a floor filling most of the view kept a right pose below min_fitness).
  ScanToCadResult res = register_points(scan.points, target, std::nullopt, params, progress, seen);
  if (params.crop_to_cad && res.registration.inliers > 0) {
    const std::vector<Eigen::Vector3f> cropped = without_background(
        scan.points, target, res.registration.source_to_target, params.icp.expected_error_mm);
    if (!cropped.empty()) {
      ScanToCadParams again = params;
      again.global_fallback = false;
      // The global pose is refined at full resolution already: from it, a coarse pass reaching 3 x 60 mm slid
      // the floor test's right pose 300 mm along its plate.
      again.icp.expected_error_mm = std::min(params.icp.expected_error_mm, 10.0);
      ScanToCadResult r = register_points(cropped, target, res.registration.source_to_target, again, progress, seen);
      if (r.valid) {
        r.used_global = true;
        res = r;
      }
    }
  }
  return res;
}

}  // namespace ewis
