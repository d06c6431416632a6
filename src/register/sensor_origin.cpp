// Is a scan in its sensor's frame: see sensor_origin.hpp.
#include "ewis/register/sensor_origin.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "ewis/core/cloud.hpp"

namespace ewis {

double occluded_fraction(const std::vector<Eigen::Vector3f>& points, const Pose& sensor_to_scan, double bin_rad,
                         double margin_mm) {
  if (points.empty()) return 0.0;
  const Eigen::Matrix3d Rt = sensor_to_scan.linear().transpose();
  const Eigen::Vector3d eye = sensor_to_scan.translation();
  struct Ray {
    double u, v, depth;
  };
  std::vector<Ray> rays;
  rays.reserve(points.size());
  std::size_t behind = 0;
  double ulo = 1e300, uhi = -1e300, vlo = 1e300, vhi = -1e300;
  for (const Eigen::Vector3f& p : points) {
    const Eigen::Vector3d q = Rt * (p.cast<double>() - eye);
    if (!(q.z() > 1e-6)) {
      ++behind;
      continue;
    }
    const Ray r{q.x() / q.z(), q.y() / q.z(), q.norm()};
    ulo = std::min(ulo, r.u), uhi = std::max(uhi, r.u), vlo = std::min(vlo, r.v), vhi = std::max(vhi, r.v);
    rays.push_back(r);
  }
  if (rays.empty()) return 1.0;
  if (!(bin_rad > 0)) {
    // About 4 points a bin over the box the rays span (an overestimate of the area they cover: fewer a bin).
    const double area = std::max((uhi - ulo) * (vhi - vlo), 1e-12);
    bin_rad = std::sqrt(area * 4.0 / static_cast<double>(rays.size()));
  }
  // Bin indices clamped below 2^30 (rays nearly parallel to the sensor's plane spread far): the key cannot overflow.
  auto index = [bin_rad](double t) { return static_cast<std::int64_t>(std::min(std::floor(t / bin_rad), 1e9)); };
  std::vector<std::pair<std::int64_t, double>> keyed(rays.size());
  for (std::size_t i = 0; i < rays.size(); ++i)
    keyed[i] = {index(rays[i].u - ulo) * (std::int64_t{1} << 31) + index(rays[i].v - vlo), rays[i].depth};
  std::sort(keyed.begin(), keyed.end());
  // Sorted by bin, then depth: each bin's second point is its second-nearest (the reference: a stray outlier in
  // front of a surface must not hide it).
  std::size_t occluded = behind;
  double reference = 0.0;
  std::size_t rank = 0;
  for (std::size_t i = 0; i < keyed.size(); ++i) {
    rank = (i == 0 || keyed[i].first != keyed[i - 1].first) ? 0 : rank + 1;
    if (rank <= 1) reference = keyed[i].second;
    else if (keyed[i].second > reference + margin_mm) ++occluded;
  }
  return static_cast<double>(occluded) / static_cast<double>(points.size());
}

double occluded_from_origin(const std::vector<Eigen::Vector3f>& points, std::size_t max_points, double margin_mm) {
  if (points.empty()) return 0.0;
  return occluded_fraction(pick(points, evenly_strided(points.size(), max_points)), Pose::Identity(), 0.0, margin_mm);
}

}  // namespace ewis
