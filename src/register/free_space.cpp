// Free space seen by the sensor (see the header).
#include "ewis/register/free_space.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "ewis/core/parallel.hpp"

namespace ewis {

std::ptrdiff_t range_bin(const RangeBins& b, const Eigen::Vector3d& p) {
  if (!(p.z() > 0.0) || !(b.bin > 0.0)) return -1;
  const double u = std::floor((p.x() / p.z() - b.lo.x()) / b.bin), v = std::floor((p.y() / p.z() - b.lo.y()) / b.bin);
  if (!(u >= 0.0 && v >= 0.0 && u < b.width && v < b.height)) return -1;
  return static_cast<std::ptrdiff_t>(v) * b.width + static_cast<std::ptrdiff_t>(u);
}

namespace {

// The angular box (u = x / z, v = y / z) of the points in front of the sensor, and their count.
struct RayBox {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = Eigen::Vector2d::Constant(-1e300);
  std::size_t n = 0;
};

RayBox ray_box(const std::vector<Eigen::Vector3f>& points) {
  // Per block, then combined in block order (the same box and count for any thread count: min, max and sums).
  return parallel_reduce_ordered(
      points.size(), 65536, RayBox{},
      [&](std::size_t b, std::size_t e) {
        RayBox box;
        for (std::size_t i = b; i < e; ++i) {
          const Eigen::Vector3f& p = points[i];
          if (!(p.z() > 0.0f)) continue;
          const Eigen::Vector3d q = p.cast<double>();  // as range_bin divides
          const Eigen::Vector2d uv(q.x() / q.z(), q.y() / q.z());
          if (!uv.allFinite()) continue;
          box.lo = box.lo.cwiseMin(uv);
          box.hi = box.hi.cwiseMax(uv);
          ++box.n;
        }
        return box;
      },
      [](RayBox a, const RayBox& b) {
        a.lo = a.lo.cwiseMin(b.lo);
        a.hi = a.hi.cwiseMax(b.hi);
        a.n += b.n;
        return a;
      });
}

RangeBins bin_in_box(const std::vector<Eigen::Vector3f>& points, const RayBox& box, double points_per_bin) {
  RangeBins b;
  if (box.n < 2) return b;
  const double per_bin = std::max(1.0, points_per_bin), count = static_cast<double>(box.n);
  const Eigen::Vector2d extent = box.hi - box.lo;
  // Sized from the box's area; at least the longer side over (count / per_bin) bins (rays in one plane: a box of
  // no area), and never zero.
  b.bin = std::max({std::sqrt(extent.prod() / count * per_bin), extent.maxCoeff() * per_bin / count, 1e-9});
  b.lo = box.lo;
  b.width = static_cast<int>(std::ceil(extent.x() / b.bin)) + 1;
  b.height = static_cast<int>(std::ceil(extent.y() / b.bin)) + 1;
  const std::size_t cells = static_cast<std::size_t>(b.width) * static_cast<std::size_t>(b.height);
  constexpr float kNone = std::numeric_limits<float>::infinity();
  // The two smallest depths per bin, of each of a few fixed parts of the points at once, then merged: the two
  // smallest of a bin's depths (equal ones counted apart) whatever part they came from.
  constexpr std::size_t kParts = 4;
  const std::size_t part = (points.size() + kParts - 1) / kParts;
  std::vector<std::vector<float>> first(kParts), second(kParts);
  parallel_for_each_index(kParts, [&](std::size_t t) {
    first[t].assign(cells, kNone);
    second[t].assign(cells, kNone);
    std::vector<float>& f = first[t];
    std::vector<float>& s2 = second[t];
    for (std::size_t j = t * part; j < std::min(points.size(), (t + 1) * part); ++j) {
      const Eigen::Vector3f& p = points[j];
      const std::ptrdiff_t k = range_bin(b, p.cast<double>());
      if (k < 0) continue;
      const std::size_t i = static_cast<std::size_t>(k);
      if (p.z() < f[i]) {
        s2[i] = f[i];
        f[i] = p.z();
      } else if (p.z() < s2[i]) {
        s2[i] = p.z();
      }
    }
  }, 1);
  for (std::size_t t = 1; t < kParts; ++t)
    for (std::size_t i = 0; i < cells; ++i)
      for (const float z : {first[t][i], second[t][i]}) {
        if (z < first[0][i]) {
          second[0][i] = first[0][i];
          first[0][i] = z;
        } else if (z < second[0][i]) {
          second[0][i] = z;
        }
      }
  std::vector<float>& nearest = second[0];
  // The second-nearest depth: one stray point in front (an outlier the filter left) does not hide the bin.
  for (std::size_t i = 0; i < cells; ++i)
    if (nearest[i] == kNone) nearest[i] = first[0][i];
  b.nearest_mm = std::move(nearest);
  return b;
}

}  // namespace

RangeBins bin_depths(const std::vector<Eigen::Vector3f>& points, double points_per_bin) {
  return bin_in_box(points, ray_box(points), points_per_bin);
}

RangeBins bin_scan_depths(const std::vector<Eigen::Vector3f>& scan, double points_per_bin) {
  const RayBox box = ray_box(scan);
  // Not a sensor's view (a scan in another frame: points behind the origin, or spread over more than +-63 deg):
  // no image, no check.
  if (box.n < 16 || static_cast<double>(box.n) < 0.99 * static_cast<double>(scan.size()) ||
      box.lo.minCoeff() < -2.0 || box.hi.maxCoeff() > 2.0)
    return RangeBins{};
  return bin_in_box(scan, box, points_per_bin);
}

FreeSpaceCount count_in_front(const RangeBins& bins, const Cloud& cad_samples, const Pose& scan_to_cad,
                              double margin_mm) {
  if (bins.bin <= 0.0) return FreeSpaceCount{};
  const Pose cad_to_scan = scan_to_cad.inverse();
  const Eigen::Vector3d eye = scan_to_cad.translation();
  const bool normals = cad_samples.normals.size() == cad_samples.points.size();
  // Counts per block, summed (exact: the same for any thread count).
  return parallel_reduce_ordered(
      cad_samples.points.size(), 16384, FreeSpaceCount{},
      [&](std::size_t b, std::size_t e) {
        FreeSpaceCount c;
        for (std::size_t i = b; i < e; ++i) {
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
      },
      [](FreeSpaceCount a, const FreeSpaceCount& b) {
        a.seen += b.seen;
        a.in_front += b.in_front;
        return a;
      });
}

}  // namespace ewis
