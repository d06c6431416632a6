#pragma once
// Pinhole camera of CONTRACT.md: square pixels, f = (width/2)/tan(hfov/2), principal point at the image
// centre, camera frame z forward (optical axis), x right, y down. Pixel (u, v) has its centre at u+0.5, v+0.5.
#include <Eigen/Core>
#include <cmath>

namespace ewis {

struct Camera {
  int width_px = 1280;
  int height_px = 1024;
  double hfov_deg = 58.0;

  double focal_px() const { return (width_px / 2.0) / std::tan(hfov_deg * M_PI / 360.0); }
  double vfov_deg() const { return 2.0 * std::atan((height_px / 2.0) / focal_px()) * 180.0 / M_PI; }
  double cx() const { return width_px / 2.0; }
  double cy() const { return height_px / 2.0; }

  // Unnormalised direction (z = 1) of the ray through image point (u, v) in camera coordinates.
  Eigen::Vector3d ray(double u, double v) const { return {(u - cx()) / focal_px(), (v - cy()) / focal_px(), 1.0}; }
  // Ray through the centre of pixel (col, row).
  Eigen::Vector3d pixel_ray(int col, int row) const { return ray(col + 0.5, row + 0.5); }

  // The projection with the focal length worked out once (a tangent), for loops over many points.
  struct Projection {
    double focal_px, cx, cy;
    // Image point of a camera-frame point; false when behind the camera.
    bool project(const Eigen::Vector3d& p_cam, double& u, double& v) const {
      if (p_cam.z() <= 0) return false;
      u = cx + focal_px * p_cam.x() / p_cam.z();
      v = cy + focal_px * p_cam.y() / p_cam.z();
      return true;
    }
  };
  Projection projection() const { return {focal_px(), cx(), cy()}; }

  // Image point of a camera-frame point; false when behind the camera.
  bool project(const Eigen::Vector3d& p_cam, double& u, double& v) const { return projection().project(p_cam, u, v); }
  bool inside(double u, double v) const { return u >= 0 && v >= 0 && u < width_px && v < height_px; }
};

}  // namespace ewis
