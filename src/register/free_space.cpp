// Free space seen by the sensor (see the header).
#include "ewis/register/free_space.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace ewis {

std::ptrdiff_t range_bin(const RangeBins& b, const Eigen::Vector3d& p) {
  if (!(p.z() > 0.0) || !(b.bin > 0.0)) return -1;
  const double u = std::floor((p.x() / p.z() - b.lo.x()) / b.bin), v = std::floor((p.y() / p.z() - b.lo.y()) / b.bin);
  if (!(u >= 0.0 && v >= 0.0 && u < b.width && v < b.height)) return -1;
  return static_cast<std::ptrdiff_t>(v) * b.width + static_cast<std::ptrdiff_t>(u);
}

RangeBins bin_depths(const std::vector<Eigen::Vector3f>& points, double points_per_bin) {
  RangeBins b;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = Eigen::Vector2d::Constant(-1e300);
  std::size_t n = 0;
  for (const Eigen::Vector3f& p : points) {
    if (!(p.z() > 0.0f)) continue;
    const Eigen::Vector3d q = p.cast<double>();  // as range_bin divides
    const Eigen::Vector2d uv(q.x() / q.z(), q.y() / q.z());
    if (!uv.allFinite()) continue;
    lo = lo.cwiseMin(uv);
    hi = hi.cwiseMax(uv);
    ++n;
  }
  if (n < 2) return b;
  const double per_bin = std::max(1.0, points_per_bin), count = static_cast<double>(n);
  const Eigen::Vector2d extent = hi - lo;
  // Sized from the box's area; at least the longer side over (count / per_bin) bins (rays in one plane: a box of
  // no area), and never zero.
  b.bin = std::max({std::sqrt(extent.prod() / count * per_bin), extent.maxCoeff() * per_bin / count, 1e-9});
  b.lo = lo;
  b.width = static_cast<int>(std::ceil(extent.x() / b.bin)) + 1;
  b.height = static_cast<int>(std::ceil(extent.y() / b.bin)) + 1;
  const std::size_t cells = static_cast<std::size_t>(b.width) * static_cast<std::size_t>(b.height);
  constexpr float kNone = std::numeric_limits<float>::infinity();
  std::vector<float> first(cells, kNone), second(cells, kNone);
  for (const Eigen::Vector3f& p : points) {
    const std::ptrdiff_t k = range_bin(b, p.cast<double>());
    if (k < 0) continue;
    const std::size_t i = static_cast<std::size_t>(k);
    if (p.z() < first[i]) {
      second[i] = first[i];
      first[i] = p.z();
    } else if (p.z() < second[i]) {
      second[i] = p.z();
    }
  }
  // The second-nearest depth: one stray point in front (an outlier the filter left) does not hide the bin.
  for (std::size_t i = 0; i < cells; ++i)
    if (second[i] == kNone) second[i] = first[i];
  b.nearest_mm = std::move(second);
  return b;
}

RangeBins bin_scan_depths(const std::vector<Eigen::Vector3f>& scan, double points_per_bin) {
  std::size_t in_front = 0;
  double reach = 0.0;  // the largest |x / z|, |y / z| of the points in front
  for (const Eigen::Vector3f& p : scan) {
    if (!(p.z() > 0.0f)) continue;
    ++in_front;
    reach = std::max({reach, std::abs(double{p.x()} / p.z()), std::abs(double{p.y()} / p.z())});
  }
  // Not a sensor's view (a scan in another frame: points behind the origin, or spread over more than +-63 deg):
  // no image, no check.
  if (in_front < 16 || static_cast<double>(in_front) < 0.99 * static_cast<double>(scan.size()) || reach > 2.0)
    return RangeBins{};
  return bin_depths(scan, points_per_bin);
}

FreeSpaceCount count_in_front(const RangeBins& bins, const Cloud& cad_samples, const Pose& scan_to_cad,
                              double margin_mm) {
  FreeSpaceCount c;
  if (bins.bin <= 0.0) return c;
  const Pose cad_to_scan = scan_to_cad.inverse();
  const Eigen::Vector3d eye = scan_to_cad.translation();
  const bool normals = cad_samples.normals.size() == cad_samples.points.size();
  for (std::size_t i = 0; i < cad_samples.points.size(); ++i) {
    const Eigen::Vector3d q = cad_samples.points[i].cast<double>();
    if (normals && cad_samples.normals[i].cast<double>().dot(eye - q) <= 0.0) continue;  // turned away
    const Eigen::Vector3d p = cad_to_scan * q;
    const std::ptrdiff_t k = range_bin(bins, p);
    if (k < 0) continue;
    const float z = bins.nearest_mm[static_cast<std::size_t>(k)];
    if (!std::isfinite(z)) continue;
    ++c.seen;
    c.in_front += p.z() < static_cast<double>(z) - margin_mm;
  }
  return c;
}

}  // namespace ewis
