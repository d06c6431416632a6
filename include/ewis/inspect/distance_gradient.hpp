#pragma once
// The outward direction from a tube's axis at a point: the gradient of the distance to its centreline, by central
// differences (the bend fits' centrelines have no closed-form closest point).
#include <Eigen/Core>

namespace ewis {

template <class Dist>
Eigen::Vector3d distance_gradient(const Dist& dist, const Eigen::Vector3d& x, double step_mm = 1e-3) {
  Eigen::Vector3d g;
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    e[a] = step_mm;
    g[a] = (dist(x + e) - dist(x - e)) / (2.0 * step_mm);
  }
  return g;
}

// The cosine between that direction and the direction from x to `sensor` (1 where the gradient is undefined).
template <class Dist>
double facing_cosine(const Dist& dist, const Eigen::Vector3d& x, const Eigen::Vector3d& sensor) {
  const Eigen::Vector3d g = distance_gradient(dist, x), v = sensor - x;
  const double gv = g.norm() * v.norm();
  return gv > 0 ? g.dot(v) / gv : 1.0;
}

}  // namespace ewis
