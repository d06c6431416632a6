// Is a scan in its sensor's frame: see sensor_origin.hpp.
#include "ewis/register/sensor_origin.hpp"

#include <Eigen/Geometry>
#include <cstddef>

#include "ewis/core/cloud.hpp"
#include "ewis/register/free_space.hpp"

namespace ewis {

double occluded_fraction(const std::vector<Eigen::Vector3f>& points, const Pose& sensor_to_scan, double points_per_bin,
                         double margin_mm) {
  if (points.empty()) return 0.0;
  const Pose scan_to_sensor = sensor_to_scan.inverse();
  std::vector<Eigen::Vector3f> seen;  // in the sensor's frame, in front of it
  seen.reserve(points.size());
  for (const Eigen::Vector3f& p : points) {
    const Eigen::Vector3d q = scan_to_sensor * p.cast<double>();
    if (q.z() > 1e-6 && q.allFinite()) seen.push_back(q.cast<float>());
  }
  // The range image keeps each bin's second-nearest depth (a stray outlier in front of a surface must not hide it).
  const RangeBins bins = bin_depths(seen, points_per_bin);
  std::size_t occluded = points.size() - seen.size();  // behind the sensor's plane
  for (const Eigen::Vector3f& q : seen) {
    const Eigen::Vector3d p = q.cast<double>();
    const std::ptrdiff_t k = range_bin(bins, p);
    if (k < 0) continue;
    // Behind along the ray: the bins hold depths along z, and a depth along z is the ray's length over
    // |p| / z (rays near the sensor's plane: a long way along the ray is little along z).
    const double behind_z = p.z() - static_cast<double>(bins.nearest_mm[static_cast<std::size_t>(k)]);
    if (behind_z * p.norm() / p.z() > margin_mm) ++occluded;
  }
  return static_cast<double>(occluded) / static_cast<double>(points.size());
}

double occluded_from_origin(const std::vector<Eigen::Vector3f>& points, std::size_t max_points, double margin_mm) {
  return occluded_from_origin(points, ScanConvention{}, max_points, margin_mm);
}

double occluded_from_origin(const std::vector<Eigen::Vector3f>& points, const ScanConvention& convention,
                            std::size_t max_points, double margin_mm) {
  if (points.empty()) return 0.0;
  Pose sensor_to_scan = Pose::Identity();
  sensor_to_scan.linear() = convention.turn.transpose();  // (the turn maps the scan into the sensor's frame)
  return occluded_fraction(pick(points, evenly_strided(points.size(), max_points)), sensor_to_scan, 4.0, margin_mm);
}

ScanConvention scan_convention(const std::vector<Eigen::Vector3f>& points) {
  ScanConvention c;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::size_t behind = 0;
  for (const Eigen::Vector3f& p : points) {
    const double n = p.cast<double>().norm();
    if (n > 0) mean += p.cast<double>() / n;
    behind += p.z() < 0.0f ? 1 : 0;
  }
  if (points.empty()) return c;
  mean /= double(points.size());
  if (mean.norm() > 0 && mean.x() > 0.7071 * mean.norm()) {
    c.turn << 0, -1, 0, 0, 0, -1, 1, 0, 0;  // x forward, y left, z up -> z forward, x right, y down
    c.looks_along = "+x";
    c.frame = "a body frame: x forward, y left, z up, as ROS's camera_link";
  } else if (2 * behind > points.size()) {
    c.turn = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
    c.looks_along = "-z";
    c.frame = "a camera frame with y up, as OpenGL's";
  }
  return c;
}

}  // namespace ewis
