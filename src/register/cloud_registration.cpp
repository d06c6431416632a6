// Cloud-to-cloud registration: PCA normals on the target, global registration without a pose, then
// point-to-plane ICP down to a few times the target's resolution.
#include "ewis/register/cloud_registration.hpp"

#include <algorithm>

#include "ewis/core/error.hpp"
#include "ewis/filter/resolution.hpp"
#include "ewis/register/point_normals.hpp"

namespace ewis {

CloudRegistrationResult register_clouds(const Cloud& source, const Cloud& target,
                                        const std::optional<Pose>& initial_source_to_target,
                                        const CloudRegistrationParams& params, const ProgressFn& progress) {
  if (source.size() < 3) throw InputError("", "registration: the source has fewer than 3 points");
  if (target.size() < 3) throw InputError("", "registration: the target has fewer than 3 points");
  CloudRegistrationResult res;
  Cloud tgt;
  tgt.points = target.points;
  const KdTree tree(tgt.points);
  res.target_resolution_mm = spatial_resolution(tree, 20000).mean_mm;
  if (target.normals.size() == target.size()) {
    tgt.normals = target.normals;
  } else {
    PointNormalParams np;
    np.k = params.normal_k;
    np.viewpoint = params.global.target_viewpoint;
    tgt.normals = estimate_point_normals(tree, np);
  }
  IcpParams icp = params.icp;
  if (icp.final_max_distance_mm <= 0) {
    // A few times the coarser of the two resolutions: a sparse model (e.g. 3 mm) against a dense scene.
    const KdTree source_tree(source.points);
    const double source_res = spatial_resolution(source_tree, 20000).mean_mm;
    icp.final_max_distance_mm = std::max({1.0, 3.0 * res.target_resolution_mm, 1.5 * source_res});
  }
  icp.noise_mm = std::max(icp.noise_mm, 0.5 * res.target_resolution_mm);

  Pose start = Pose::Identity();
  if (initial_source_to_target) {
    start = *initial_source_to_target;
  } else {
    const GlobalRegistrationResult g = register_global(source, target, params.global, progress);
    res.used_global = true;
    start = g.registration.source_to_target;
    icp.expected_error_mm = std::max(2.0 * g.voxel_mm, icp.final_max_distance_mm);
  }
  res.registration = align_point_to_plane(source.points, tgt, tree, start, icp, {}, progress);
  res.valid = res.registration.fitness >= params.min_fitness;
  return res;
}

}  // namespace ewis
