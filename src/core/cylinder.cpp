#include "ewis/core/cylinder.hpp"

#include <algorithm>

namespace ewis {

double distance_to_axis(const Cylinder& c, const Eigen::Vector3d& p) {
  const Eigen::Vector3d a = c.axis();
  const Eigen::Vector3d d = p - c.start;
  return (d - a * a.dot(d)).norm();
}

double distance_to_segment(const Cylinder& c, const Eigen::Vector3d& p) {
  const Eigen::Vector3d ab = c.end - c.start;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - c.start).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (c.start + t * ab)).norm();
}

}  // namespace ewis
