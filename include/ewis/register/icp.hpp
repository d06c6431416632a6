#pragma once
// Local registration (paper 4.1.2): point-to-plane ICP solved by Gauss-Newton with Levenberg-Marquardt damping
// over a 6-DoF twist, a robust (Cauchy) kernel and a shrinking correspondence distance.
// Shaped like small_gicp's align(target, source, init_T, setting): plain Params and Result structs.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "ewis/core/cloud.hpp"
#include "ewis/core/pose.hpp"
#include "ewis/core/progress.hpp"
#include <memory>

#include "ewis/search/kdtree.hpp"
#include "ewis/search/moving_nearest.hpp"

namespace ewis {

struct IcpParams {
  // Correspondence distance schedule: stages from initial_max_distance_mm down to final_max_distance_mm, each
  // stage `distance_shrink` times the previous one. initial <= 0: max(3 x expected_error_mm, 10 mm).
  double expected_error_mm = 10.0;      // how far (mm, at the scene's points) the initial pose may be off
  double initial_max_distance_mm = 0.0;
  double final_max_distance_mm = 1.0;   // ~1 mm or a few x the resolution; also the fitness inlier distance
  double distance_shrink = 0.5;
  int max_iterations_per_stage = 30;
  int max_iterations = 200;             // over all stages (bounds every run)
  // Robust kernel (Cauchy): scale = max(kernel_noise_factor x noise_mm, stage max distance / kernel_distance_div).
  double noise_mm = 0.2;                // expected noise of the source (sigma)
  double kernel_noise_factor = 3.0;
  double kernel_distance_div = 3.0;
  // Convergence: an iteration whose update is below both limits ends the stage.
  double converge_rotation_deg = 1e-4;
  double converge_translation_mm = 1e-4;
  // Levenberg-Marquardt damping (relative to diag(H)); retried up to lm_max_tries times per iteration.
  double lm_initial_lambda = 1e-4;
  int lm_max_tries = 10;
  // Coarse stages (max distance > coarse_distance_mm, or > 4 x final when that is <= 0) use at most this many
  // source points (evenly strided); 0: all.
  std::size_t coarse_max_points = 20000;
  double coarse_distance_mm = 0.0;
  // The other stages use at most this many (evenly strided; 0: all): a pose has 6 unknowns, 10^5 points pin it
  // far below the noise. Fitness and rmse are still measured over every source point.
  std::size_t max_points = 100000;
  int min_correspondences = 6;
  // Visibility: when set, the source was seen from this point (in source coordinates: the sensor, the origin of
  // a scan's frame) and target points whose normal faces away from it are never matched, so a scanned plate's
  // top cannot lock onto the CAD plate's bottom face. Needs outward (consistently wound) target normals.
  bool use_source_viewpoint = false;
  Eigen::Vector3d source_viewpoint = Eigen::Vector3d::Zero();
};

// The Cauchy kernel's scale (mm) of a stage whose correspondences reach `max_distance_mm` (see IcpParams).
double icp_kernel_scale_mm(const IcpParams& params, double max_distance_mm);

// Result of a registration (local or global). pose maps the source into the target frame.
struct RegistrationResult {
  Pose source_to_target = Pose::Identity();
  double rmse_mm = 0.0;          // RMS point-to-plane residual of the final inliers
  double fitness = 0.0;          // fraction of source points with a target neighbour within inlier_distance_mm
  std::size_t inliers = 0;       // that count
  double inlier_distance_mm = 0.0;
  int iterations = 0;
  bool converged = false;        // the final stage met the update-size test
};

// What an alignment learnt about each source point's correspondence (its last target point; for the points it
// used, the target points nearest to where each last was), handed on to the next alignment of the same source onto
// the same target tree (a refinement's coarse and fine passes). Only the time depends on it, never the answer.
// Memory: 4 bytes a source point and 52 a used one (at most IcpParams::max_points).
struct IcpMemory {
  const KdTree* tree = nullptr;  // what it was learnt on (another tree: it starts afresh)
  std::vector<std::uint32_t> hint;
  std::unique_ptr<MovingNearest> near;
};

// Aligns `source` onto `target` (points with unit normals; `target_tree` is its k-d tree), starting at
// `initial_source_to_target`. `source_indices` selects the source points to use (empty: all). Deterministic for
// any thread count. Throws InputError when the target has no normals or the two clouds are empty.
RegistrationResult align_point_to_plane(const std::vector<Eigen::Vector3f>& source, const Cloud& target,
                                        const KdTree& target_tree, const Pose& initial_source_to_target,
                                        const IcpParams& params = {},
                                        const std::vector<std::uint32_t>& source_indices = {},
                                        const ProgressFn& progress = {}, IcpMemory* memory = nullptr);

// Fitness/rmse of a pose without moving it: the fraction of source points whose nearest target point is within
// inlier_distance_mm, and the RMS point-to-plane residual of those. Used to validate and compare poses.
RegistrationResult evaluate_registration(const std::vector<Eigen::Vector3f>& source, const Cloud& target,
                                         const KdTree& target_tree, const Pose& source_to_target,
                                         double inlier_distance_mm,
                                         const std::vector<std::uint32_t>& source_indices = {});

}  // namespace ewis
