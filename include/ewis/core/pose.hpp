#pragma once
// Poses are rigid transforms in double; names say the direction (scan_to_cad, camera_to_cad).
#include <Eigen/Geometry>
#include <string>

namespace ewis {

using Pose = Eigen::Isometry3d;

// Rotation angle (deg) and translation (mm) between two poses: |a^-1 b|.
double rotation_error_deg(const Pose& a, const Pose& b);
double translation_error_mm(const Pose& a, const Pose& b);

// Rotation about unit axis by angle_deg, then translation.
Pose make_pose(const Eigen::Vector3d& axis, double angle_deg, const Eigen::Vector3d& translation_mm);

// A camera at `position` looking at `target`, z forward, x right, y down (CONTRACT.md camera frame).
// `up_hint` is the world direction that appears up in the image (-y); a fallback is chosen when parallel.
Pose look_at(const Eigen::Vector3d& position, const Eigen::Vector3d& target,
             const Eigen::Vector3d& up_hint = Eigen::Vector3d::UnitZ());

}  // namespace ewis
