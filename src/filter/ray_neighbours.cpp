// The points on the rays next to a point's own (see ray_neighbours.hpp).
#include "ewis/filter/ray_neighbours.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Dense>

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

RaySurface seen_surface_at(const KdTree& tree, std::uint32_t self, const Eigen::Vector3d& p,
                           const Eigen::Vector3d& viewpoint, const RaySurfaceParams& params,
                           std::vector<Neighbor>& scratch) {
  RaySurface out;
  const Eigen::Vector3d ray = p - viewpoint;
  if (!(ray.norm() > 0) || params.rays < 3) return out;
  const Eigen::Vector3d u = ray.normalized();
  const Eigen::Vector3d e1 = u.unitOrthogonal(), e2 = u.cross(e1);
  const double reach = std::max(params.reach_mm, params.tolerance_mm);
  const double lateral_sq = params.lateral_mm * params.lateral_mm;
  tree.radius_unsorted(p.cast<float>(), float(std::hypot(reach, params.lateral_mm)), scratch);
  struct Near {
    double lateral_sq;
    std::uint32_t index;
    Eigen::Vector2d at;  // lateral coordinates
    double along;
  };
  std::vector<Near> near;
  near.reserve(scratch.size());
  const double own_sq = params.same_ray_mm * params.same_ray_mm;
  for (const Neighbor& n : scratch) {
    if (n.index == self) continue;
    const Eigen::Vector3d d = tree.points()[n.index].cast<double>() - p;
    const double along = d.dot(u);
    const Eigen::Vector2d at(d.dot(e1), d.dot(e2));
    const double lsq = at.squaredNorm();
    if (std::abs(along) > reach || lsq > lateral_sq || lsq < own_sq) continue;  // out of reach, or on its own ray
    near.push_back({lsq, n.index, at, along});
  }
  std::sort(near.begin(), near.end(), [](const Near& x, const Near& y) {
    return x.lateral_sq != y.lateral_sq ? x.lateral_sq < y.lateral_sq : x.index < y.index;
  });
  // The nearest `rays` rays around it; the points of one ray (a stack: a sensor's mixed or repeated ranges) together,
  // up to kPerRay of them, the nearest to its range first.
  constexpr std::size_t kPerRay = 4;
  struct Ray {
    Eigen::Vector2d at;
    std::vector<double> along;
  };
  std::vector<Ray> rays;
  for (const Near& n : near) {
    auto it = std::find_if(rays.begin(), rays.end(),
                           [&](const Ray& r) { return (r.at - n.at).squaredNorm() < own_sq; });
    if (it != rays.end()) {
      it->along.push_back(n.along);
    } else if (rays.size() < params.rays) {
      rays.push_back({n.at, {n.along}});
    } else if (std::sqrt(n.lateral_sq) > rays.back().at.norm() + params.same_ray_mm) {
      break;  // past every chosen ray (the farthest is the last)
    }
  }
  for (Ray& r : rays) {
    std::sort(r.along.begin(), r.along.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
    if (r.along.size() > kPerRay) r.along.resize(kPerRay);
  }
  const std::size_t k = rays.size();
  out.neighbours = k;
  if (k < std::max<std::size_t>(3, params.min_inliers)) return out;
  // A plane along = g . lateral + c through one point of each of three rays; held by the rays with a point within
  // tolerance_mm of it. The one most rays hold wins, then the one nearest the point.
  // The ray's range nearest the plane.
  const auto nearest = [](const Ray& r, const Eigen::Vector3d& plane) {
    const double at = plane.x() * r.at.x() + plane.y() * r.at.y() + plane.z();
    double along = r.along.front();
    for (double a : r.along)
      if (std::abs(a - at) < std::abs(along - at)) along = a;
    return std::pair<double, double>{along, std::abs(along - at)};
  };
  const auto holding = [&](const Eigen::Vector3d& plane) {
    std::size_t count = 0;
    for (const Ray& r : rays) count += nearest(r, plane).second <= params.tolerance_mm;
    return count;
  };
  const double min_det = 0.01 * lateral_sq;
  std::size_t best = 0;
  Eigen::Vector3d best_plane = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = i + 1; j < k; ++j)
      for (std::size_t l = j + 1; l < k; ++l) {
        Eigen::Matrix3d m;
        m << rays[i].at.x(), rays[i].at.y(), 1.0, rays[j].at.x(), rays[j].at.y(), 1.0, rays[l].at.x(), rays[l].at.y(),
            1.0;
        const double det = m.determinant();
        if (std::abs(det) < min_det) continue;
        const Eigen::Matrix3d inv = m.inverse();
        for (double ai : rays[i].along)
          for (double aj : rays[j].along)
            for (double al : rays[l].along) {
              const Eigen::Vector3d plane = inv * Eigen::Vector3d(ai, aj, al);
              const std::size_t count = holding(plane);
              if (count > best || (count == best && std::abs(plane.z()) < std::abs(best_plane.z()))) {
                best = count;
                best_plane = plane;
              }
            }
      }
  if (best < 3) return out;
  // Refitted (least squares) to the point of each ray holding it that lies nearest it.
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atb = Eigen::Vector3d::Zero();
  std::size_t inliers = 0;
  for (const Ray& r : rays) {
    const auto [along, off] = nearest(r, best_plane);
    if (off > params.tolerance_mm) continue;
    const Eigen::Vector3d row(r.at.x(), r.at.y(), 1.0);
    ata += row * row.transpose();
    atb += row * along;
    ++inliers;
  }
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(ata);
  const Eigen::Vector3d plane = ldlt.info() == Eigen::Success ? Eigen::Vector3d(ldlt.solve(atb)) : best_plane;
  out.inliers = inliers;
  out.offset_mm = plane.z();
  out.on = inliers >= params.min_inliers && std::abs(out.offset_mm) <= params.tolerance_mm;
  return out;
}

}  // namespace ewis
