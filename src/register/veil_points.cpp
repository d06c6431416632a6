// Veil (mixed pixel) detection by the angle between a point's PCA normal and its viewing ray: see
// veil_points.hpp.
#include "ewis/register/veil_points.hpp"

#include "ewis/core/parallel.hpp"
#include "ewis/filter/normals.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis {

std::vector<std::uint32_t> points_off_veils(const std::vector<Eigen::Vector3f>& points,
                                            const Eigen::Vector3d& viewpoint, const VeilParams& params) {
  if (points.size() < 3) return parallel_select(points.size(), [](std::size_t) { return true; });
  const KdTree tree(points);
  NormalParams np;
  np.k = std::max(params.k, 3);
  np.viewpoint = viewpoint.cast<float>();
  const std::vector<Eigen::Vector3f> normals = estimate_normals(tree, np);
  return parallel_select(points.size(), [&](std::size_t i) {
    if (normals[i].squaredNorm() == 0) return true;
    const Eigen::Vector3d ray = points[i].cast<double>() - viewpoint;
    const double len = ray.norm();
    if (!(len > 0)) return true;
    return std::abs(normals[i].cast<double>().dot(ray)) >= params.cos_max * len;
  });
}

}  // namespace ewis
