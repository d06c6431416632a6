#include "ewis/core/pose.hpp"

#include <algorithm>
#include <cmath>

namespace ewis {

double rotation_error_deg(const Pose& a, const Pose& b) {
  const Eigen::Matrix3d r = a.linear().transpose() * b.linear();
  const double c = std::clamp((r.trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c) * 180.0 / M_PI;
}

double translation_error_mm(const Pose& a, const Pose& b) { return (a.translation() - b.translation()).norm(); }

Pose make_pose(const Eigen::Vector3d& axis, double angle_deg, const Eigen::Vector3d& translation_mm) {
  Pose p = Pose::Identity();
  if (axis.norm() > 0) p.linear() = Eigen::AngleAxisd(angle_deg * M_PI / 180.0, axis.normalized()).toRotationMatrix();
  p.translation() = translation_mm;
  return p;
}

Pose look_at(const Eigen::Vector3d& position, const Eigen::Vector3d& target, const Eigen::Vector3d& up_hint) {
  const Eigen::Vector3d z = (target - position).normalized();
  Eigen::Vector3d up = up_hint.normalized();
  if (std::abs(z.dot(up)) > 0.999) up = std::abs(z.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d x = z.cross(up).normalized();  // right
  const Eigen::Vector3d y = z.cross(x);                 // down
  Pose p = Pose::Identity();
  p.linear().col(0) = x;
  p.linear().col(1) = y;
  p.linear().col(2) = z;
  p.translation() = position;
  return p;
}

}  // namespace ewis
