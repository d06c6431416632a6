// The points on the rays next to a point's own (see ray_neighbours.hpp).
#include "ewis/filter/ray_neighbours.hpp"

#include <algorithm>
#include <cmath>

namespace ewis {

RayNeighbours ray_neighbours(const KdTree& tree, std::uint32_t self, const Eigen::Vector3d& p,
                             const Eigen::Vector3d& viewpoint, const RayNeighbourParams& params,
                             std::vector<Neighbor>& scratch) {
  RayNeighbours out;
  const Eigen::Vector3d ray = p - viewpoint;
  if (!(ray.norm() > 0)) return out;
  const Eigen::Vector3d u = ray.normalized();
  const double reach = std::max(params.reach_mm, params.tolerance_mm);
  const double lateral_sq = params.lateral_mm * params.lateral_mm;
  tree.radius_unsorted(p.cast<float>(), float(std::hypot(reach, params.lateral_mm)), scratch);
  for (const Neighbor& n : scratch) {
    if (n.index == self) continue;
    const Eigen::Vector3d d = tree.points()[n.index].cast<double>() - p;
    const double along = d.dot(u);
    if (std::abs(along) > reach || (d - along * u).squaredNorm() > lateral_sq) continue;
    if (along > params.tolerance_mm)
      ++out.behind;
    else if (along < -params.tolerance_mm)
      ++out.front;
    else
      ++out.same;
  }
  return out;
}

}  // namespace ewis
