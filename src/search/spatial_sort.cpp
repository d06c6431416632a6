// sort_for_search: the tree's leaf order applied to every attribute of the cloud, in place.
#include "ewis/search/spatial_sort.hpp"

#include <cstdint>
#include <utility>
#include <vector>

#include "ewis/search/kdtree.hpp"

namespace ewis {

void sort_for_search(Cloud& cloud) {
  const std::size_t n = cloud.points.size();
  // new[j] = old[order[j]]: the finite points in leaf order, then the others in their order
  std::vector<std::uint32_t> order = spatial_sort_order(cloud.points);
  if (order.size() < n) {
    std::vector<bool> placed(n, false);
    for (std::uint32_t i : order) placed[i] = true;
    for (std::size_t i = 0; i < n; ++i)
      if (!placed[i]) order.push_back(static_cast<std::uint32_t>(i));
  }
  // In place, cycle by cycle, every attribute together (no copy of any of them); order[j] = j marks a slot done.
  auto move_slot = [&](std::size_t to, std::size_t from) {
    cloud.points[to] = cloud.points[from];
    if (!cloud.normals.empty()) cloud.normals[to] = cloud.normals[from];
    if (!cloud.colors.empty()) cloud.colors[to] = cloud.colors[from];
    if (!cloud.intensities.empty()) cloud.intensities[to] = cloud.intensities[from];
    for (ScalarField& f : cloud.scalars) f.values[to] = f.values[from];
  };
  Cloud first;  // the cycle's first slot, held aside
  first.scalars = cloud.scalars;
  for (ScalarField& f : first.scalars) f.values.assign(1, 0.0f);
  auto hold = [&](std::size_t j) {
    first.points.assign(1, cloud.points[j]);
    if (!cloud.normals.empty()) first.normals.assign(1, cloud.normals[j]);
    if (!cloud.colors.empty()) first.colors.assign(1, cloud.colors[j]);
    if (!cloud.intensities.empty()) first.intensities.assign(1, cloud.intensities[j]);
    for (std::size_t s = 0; s < cloud.scalars.size(); ++s) first.scalars[s].values[0] = cloud.scalars[s].values[j];
  };
  auto put = [&](std::size_t j) {
    cloud.points[j] = first.points[0];
    if (!cloud.normals.empty()) cloud.normals[j] = first.normals[0];
    if (!cloud.colors.empty()) cloud.colors[j] = first.colors[0];
    if (!cloud.intensities.empty()) cloud.intensities[j] = first.intensities[0];
    for (std::size_t s = 0; s < cloud.scalars.size(); ++s) cloud.scalars[s].values[j] = first.scalars[s].values[0];
  };
  for (std::size_t start = 0; start < n; ++start) {
    if (order[start] == start) continue;
    hold(start);
    std::size_t j = start;
    while (order[j] != start) {
      const std::size_t from = order[j];
      move_slot(j, from);
      order[j] = static_cast<std::uint32_t>(j);
      j = from;
    }
    put(j);
    order[j] = static_cast<std::uint32_t>(j);
  }
}

}  // namespace ewis
