// Voxel-grid down-sampling (the re-sampling of paper 4.1.1 before registration): one point per occupied voxel.
#include "ewis/filter/voxel_grid.hpp"

#include <tbb/parallel_sort.h>

#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "ewis/core/error.hpp"
#include "ewis/core/parallel.hpp"

namespace ewis {
namespace {

bool is_finite(const Eigen::Vector3f& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()); }

}  // namespace

VoxelGridResult voxel_downsample(const Cloud& cloud, double voxel_mm) {
  if (!(voxel_mm > 0) || !std::isfinite(voxel_mm))
    throw InputError("", "voxel size must be a positive number of mm, got " + std::to_string(voxel_mm));
  VoxelGridResult result;
  const std::size_t n = cloud.size();

  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& p : cloud.points)
    if (is_finite(p)) {
      lo = lo.cwiseMin(p.cast<double>());
      hi = hi.cwiseMax(p.cast<double>());
    }
  if (!(lo.x() <= hi.x())) return result;  // empty, or no finite point

  // Voxel counts per axis; keys are z-major linear indices, so they must fit in 63 bits.
  std::uint64_t dims[3];
  double cells = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double d = std::floor((hi[a] - lo[a]) / voxel_mm) + 1.0;
    cells *= d;
    if (!std::isfinite(d) || cells >= 9.0e18)
      throw InputError("", "voxel size " + std::to_string(voxel_mm) + " mm is too small for the cloud's extent");
    dims[a] = static_cast<std::uint64_t>(d);
  }
  auto key_of = [&](const Eigen::Vector3f& p) {
    std::uint64_t idx[3];
    for (int a = 0; a < 3; ++a) {
      const double c = std::floor((p[a] - lo[a]) / voxel_mm);
      idx[a] = std::min<std::uint64_t>(static_cast<std::uint64_t>(std::max(0.0, c)), dims[a] - 1);
    }
    return idx[0] + dims[0] * (idx[1] + dims[1] * idx[2]);
  };

  // (key, index) pairs are unique, so even an unstable parallel sort gives one order.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(n);
  parallel_for_each_index(n, [&](std::size_t i) {
    keyed[i] = {is_finite(cloud.points[i]) ? key_of(cloud.points[i]) : ~std::uint64_t{0},
                static_cast<std::uint32_t>(i)};
  });
  tbb::parallel_sort(keyed.begin(), keyed.end());

  constexpr std::uint64_t kNonFinite = std::numeric_limits<std::uint64_t>::max();  // sorted last
  std::vector<std::size_t> starts;
  std::size_t finite_end = 0;
  for (; finite_end < n && keyed[finite_end].first != kNonFinite; ++finite_end)
    if (finite_end == 0 || keyed[finite_end].first != keyed[finite_end - 1].first) starts.push_back(finite_end);
  const std::size_t m = starts.size();
  starts.push_back(finite_end);

  Cloud& out = result.cloud;
  out.points.resize(m);
  result.representative.resize(m);
  if (cloud.has_normals()) out.normals.resize(m);
  if (cloud.has_colors()) out.colors.resize(m);
  if (cloud.has_intensities()) out.intensities.resize(m);
  for (const auto& f : cloud.scalars) out.scalars.push_back({f.name, std::vector<float>(m)});

  parallel_for_each_index(m, [&](std::size_t v) {
    const std::size_t b = starts[v], e = starts[v + 1];
    const double cnt = static_cast<double>(e - b);
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (std::size_t j = b; j < e; ++j) c += cloud.points[keyed[j].second].cast<double>();
    c /= cnt;
    out.points[v] = c.cast<float>();
    // representative: the input point nearest the centroid, ties to the smallest index (runs are sorted)
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t j = b; j < e; ++j) {
      const double d = (cloud.points[keyed[j].second].cast<double>() - c).squaredNorm();
      if (d < best) {
        best = d;
        result.representative[v] = keyed[j].second;
      }
    }
    if (cloud.has_normals()) {
      Eigen::Vector3d s = Eigen::Vector3d::Zero();
      for (std::size_t j = b; j < e; ++j) s += cloud.normals[keyed[j].second].cast<double>();
      // opposite normals cancel: fall back to the representative's
      out.normals[v] = s.norm() > 1e-12 ? s.normalized().cast<float>() : cloud.normals[result.representative[v]];
    }
    if (cloud.has_colors()) {
      double rgb[3] = {0, 0, 0};
      for (std::size_t j = b; j < e; ++j)
        for (int a = 0; a < 3; ++a) rgb[a] += cloud.colors[keyed[j].second][a];
      for (int a = 0; a < 3; ++a) out.colors[v][a] = static_cast<std::uint8_t>(std::lround(rgb[a] / cnt));
    }
    if (cloud.has_intensities()) {
      double s = 0;
      for (std::size_t j = b; j < e; ++j) s += cloud.intensities[keyed[j].second];
      out.intensities[v] = static_cast<float>(s / cnt);
    }
    for (std::size_t f = 0; f < cloud.scalars.size(); ++f) {
      const auto& vals = cloud.scalars[f].values;
      if (vals.size() != n) continue;
      double s = 0;
      for (std::size_t j = b; j < e; ++j) s += vals[keyed[j].second];
      out.scalars[f].values[v] = static_cast<float>(s / cnt);
    }
  });
  return result;
}

}  // namespace ewis
