#include "ewis/core/cloud.hpp"

namespace ewis {

namespace {
template <class T>
std::vector<T> pick(const std::vector<T>& v, const std::vector<std::uint32_t>& idx) {
  std::vector<T> out;
  if (v.empty()) return out;
  out.reserve(idx.size());
  for (auto i : idx) out.push_back(v[i]);
  return out;
}
}  // namespace

Cloud select(const Cloud& cloud, const std::vector<std::uint32_t>& indices) {
  Cloud out;
  out.points = pick(cloud.points, indices);
  out.normals = pick(cloud.normals, indices);
  out.colors = pick(cloud.colors, indices);
  out.intensities = pick(cloud.intensities, indices);
  for (const auto& s : cloud.scalars) out.scalars.push_back({s.name, pick(s.values, indices)});
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
