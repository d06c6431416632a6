// Scan-to-CAD registration on the rigid elements (paper 4.1.2, 4.2): ICP from the initial pose (or from the
// global registration's pose), in two passes: a coarse pass with the cable exclusion zone widened by the pose
// uncertainty, then a fine pass with the zone re-evaluated at the refined pose.
#include "ewis/register/scan_to_cad.hpp"

#include <algorithm>

#include "ewis/core/error.hpp"

namespace ewis {
namespace {

struct Run {
  RegistrationResult reg;
  std::size_t excluded = 0;
};

Run refine(const Cloud& scan, const CadTarget& target, const Pose& start, double expected_error_mm,
           const ScanToCadParams& params, const ProgressFn& progress) {
  IcpParams icp = params.icp;
  // Final distance: ~1 mm, but never below what the sampling spacing and the noise need.
  const double final_d = std::max(icp.final_max_distance_mm, target.spacing_mm + 3.0 * icp.noise_mm);
  icp.final_max_distance_mm = final_d;
  icp.expected_error_mm = expected_error_mm;

  // While the pose is uncertain, the zone around each cable grows by that uncertainty (bounded, so that a
  // scene with many cables keeps enough rigid points).
  std::vector<std::uint32_t> keep =
      points_away_from_cables(scan.points, start, target, std::min(expected_error_mm, 20.0));
  if (keep.size() < std::max<std::size_t>(50, scan.size() / 10))
    keep = points_away_from_cables(scan.points, start, target, 0.0);
  Run run;
  if (keep.size() < 6) return run;
  const RegistrationResult coarse =
      align_point_to_plane(scan.points, target.rigid, *target.rigid_tree, start, icp, keep, progress);

  keep = points_away_from_cables(scan.points, coarse.source_to_target, target, 0.0);
  if (keep.size() < 6) return run;
  IcpParams fine = icp;
  fine.initial_max_distance_mm = std::max(3.0 * final_d, 4.0);
  run.reg = align_point_to_plane(scan.points, target.rigid, *target.rigid_tree, coarse.source_to_target, fine, keep);
  run.reg.iterations += coarse.iterations;
  run.excluded = scan.size() - keep.size();
  return run;
}

}  // namespace

ScanToCadResult register_scan_to_cad(const Cloud& scan, const CadTarget& target,
                                     const std::optional<Pose>& initial_scan_to_cad, const ScanToCadParams& params,
                                     const ProgressFn& progress) {
  if (scan.empty()) throw InputError("", "registration: the scan has no points");
  if (!target.rigid_tree || target.rigid.empty()) throw InputError("", "registration: empty CAD target");
  ScanToCadResult res;
  bool have = false;
  auto consider = [&](const Run& r, bool global) {
    if (r.reg.inliers == 0 && have) return;
    if (!have || r.reg.fitness > res.registration.fitness) {
      res.registration = r.reg;
      res.excluded_near_cables = r.excluded;
      res.used_global = global;
      have = true;
    }
  };
  if (initial_scan_to_cad) consider(refine(scan, target, *initial_scan_to_cad, params.icp.expected_error_mm, params, progress), false);
  const bool ok = have && res.registration.fitness >= params.min_fitness;
  if (!initial_scan_to_cad || (!ok && params.global_fallback)) {
    const GlobalRegistrationResult g = register_global(scan, target.rigid, params.global, progress);
    // Symmetric parts of a scene (a plate, rows of blocks) give near-ties at the coarse scale: re-rank all the
    // candidates by their fitness on the full-resolution target at a tighter distance, then the full ICP of the
    // first few decides.
    std::vector<std::uint32_t> probe;
    const std::size_t stride = std::max<std::size_t>(1, scan.size() / 8000);
    for (std::size_t i = 0; i < scan.size(); i += stride) probe.push_back(static_cast<std::uint32_t>(i));
    const double tight = std::max(0.4 * g.voxel_mm, 3.0);
    std::vector<std::pair<double, std::size_t>> ranked;
    for (std::size_t i = 0; i < g.candidates.size(); ++i)
      ranked.emplace_back(evaluate_registration(scan.points, target.rigid, *target.rigid_tree,
                                                g.candidates[i].source_to_target, tight, probe)
                              .fitness,
                          i);
    std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    const std::size_t n = std::min<std::size_t>(ranked.size(), std::max(1, params.global_candidates));
    for (std::size_t i = 0; i < n; ++i)
      consider(refine(scan, target, g.candidates[ranked[i].second].source_to_target, std::max(2.0 * g.voxel_mm, 5.0),
                      params, progress),
               true);
  }
  res.valid = have && res.registration.fitness >= params.min_fitness;
  if (!res.valid && params.icp.use_source_viewpoint) {
    // The scan may not be in its sensor's frame after all: retry once without visibility culling.
    ScanToCadParams plain = params;
    plain.icp.use_source_viewpoint = false;
    ScanToCadResult retry = register_scan_to_cad(scan, target, initial_scan_to_cad, plain, progress);
    if (retry.registration.fitness > res.registration.fitness) res = retry;
  }
  return res;
}

}  // namespace ewis
