#include "ewis/core/cloud.hpp"

namespace ewis {


Cloud select(const Cloud& cloud, const std::vector<std::uint32_t>& indices) {
  Cloud out;
  out.points = pick(cloud.points, indices);
  out.normals = pick(cloud.normals, indices);
  out.colors = pick(cloud.colors, indices);
  out.intensities = pick(cloud.intensities, indices);
  for (const auto& s : cloud.scalars) out.scalars.push_back({s.name, pick(s.values, indices)});
  return out;
}

std::vector<std::uint32_t> evenly_strided(std::size_t n, std::size_t max_count) {
  const std::size_t m = max_count == 0 ? n : std::min(n, max_count);
  std::vector<std::uint32_t> out(m);
  const double step = static_cast<double>(n) / static_cast<double>(std::max<std::size_t>(m, 1));
  for (std::size_t i = 0; i < m; ++i)
    out[i] = static_cast<std::uint32_t>(m == n ? i : static_cast<std::size_t>(static_cast<double>(i) * step));
  return out;
}

bool bounds(const std::vector<Eigen::Vector3f>& points, Eigen::Vector3f& min_out, Eigen::Vector3f& max_out) {
  if (points.empty()) return false;
  min_out = max_out = points.front();
  for (const auto& p : points) {
    min_out = min_out.cwiseMin(p);
    max_out = max_out.cwiseMax(p);
  }
  return true;
}

void scale(Cloud& cloud, float factor) {
  for (auto& p : cloud.points) p *= factor;
}

}  // namespace ewis
