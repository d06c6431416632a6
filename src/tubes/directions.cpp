// paper 4.2.2: candidate axes through the sphere's centre; one per antipodal pair, so a hemisphere suffices.
#include "ewis/tubes/directions.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace ewis {
namespace {
constexpr double kGoldenAngle = 2.39996322972865332;  // pi (3 - sqrt 5)
}

std::vector<Eigen::Vector3d> hemisphere_directions(int count) {
  count = std::max(count, 1);
  std::vector<Eigen::Vector3d> dirs;
  dirs.reserve(count);
  // equal-area lattice: z uniform in (0, 1] gives equal area bands on the hemisphere
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (i + 0.5) / count;
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = i * kGoldenAngle;
    dirs.emplace_back(s * std::cos(phi), s * std::sin(phi), z);
  }
  return dirs;
}

std::vector<Eigen::Vector3d> cone_directions(double half_angle_deg, double spacing_deg) {
  const double theta = std::clamp(half_angle_deg, 0.0, 90.0) * M_PI / 180.0;
  const double step = std::max(spacing_deg, 0.01) * M_PI / 180.0;
  const double cap = 2.0 * M_PI * (1.0 - std::cos(theta));  // solid angle of the cone
  const int count = std::clamp(static_cast<int>(std::ceil(cap / (step * step))), 0, 200000);
  std::vector<Eigen::Vector3d> dirs;
  dirs.reserve(count + 1);
  dirs.emplace_back(0, 0, 1);
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (i + 0.5) / count * (1.0 - std::cos(theta));
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = i * kGoldenAngle;
    dirs.emplace_back(s * std::cos(phi), s * std::sin(phi), z);
  }
  return dirs;
}

Eigen::Matrix3d rotation_from_z(const Eigen::Vector3d& d) {
  const Eigen::Vector3d w = d.normalized();
  // the coordinate axis least aligned with w gives a well-conditioned perpendicular
  int k = 0;
  if (std::abs(w.y()) < std::abs(w[k])) k = 1;
  if (std::abs(w.z()) < std::abs(w[k])) k = 2;
  Eigen::Vector3d e = Eigen::Vector3d::Zero();
  e[k] = 1.0;
  const Eigen::Vector3d e1 = (e - w * w.dot(e)).normalized();
  const Eigen::Vector3d e2 = w.cross(e1);
  Eigen::Matrix3d r;
  r.col(0) = e1;
  r.col(1) = e2;
  r.col(2) = w;
  return r;
}

}  // namespace ewis
