#pragma once
// The registration's last step on the CAD's exact surface. The ICP (icp.hpp) matches each scan point to its
// nearest CAD *sample* and that sample's normal. Near an edge the nearest sample often lies on the adjacent face:
// points of a bracket's thin top face matched to its big side face's samples by the edge (their residuals spread
// evenly over +-1 mm, not a 0.2 mm peak), and on a plate whose in-plane directions only those thin faces pin,
// that bias moved the pose ~0.4 mm (docs/register.md, "Registration on weakly constrained scenes"). Here each
// point is matched to its exact closest point on the rigid elements' triangles (SurfaceIndex) and the residual is
// its distance to the surface, along the direction to that point: faces, edges and corners all pull as they should.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "ewis/core/pose.hpp"
#include "ewis/register/icp.hpp"
#include "ewis/scene/surface_index.hpp"

namespace ewis {

struct SurfaceRefineParams {
  double max_distance_mm = 1.0;   // correspondences farther from the surface are left out
  double kernel_mm = 0.6;         // Cauchy kernel scale
  int max_iterations = 10;
  double converge_rotation_deg = 1e-4;
  double converge_translation_mm = 1e-4;
};

// Gauss-Newton on the distance of `source[indices]` (all when empty) to `surface`, from `start` (source to
// surface coordinates). fitness and rmse over the points used, as align_point_to_plane gives them. Deterministic
// for any thread count.
RegistrationResult refine_on_surface(const std::vector<Eigen::Vector3f>& source, const SurfaceIndex& surface,
                                     const Pose& start, const SurfaceRefineParams& params = {},
                                     const std::vector<std::uint32_t>& indices = {});

}  // namespace ewis
