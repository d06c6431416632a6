// sort_for_search: the tree's leaf order applied to every attribute of the cloud, in place.
#include "ewis/search/spatial_sort.hpp"

#include <cstdint>
#include <vector>

#include "ewis/search/kdtree.hpp"

namespace ewis {
namespace {

// values[j] = old values[order[j]] for every j, cycle by cycle in place; `done` marks the slots already set.
template <class T>
void permute(std::vector<T>& values, const std::vector<std::uint32_t>& order, std::vector<bool>& done) {
  if (values.empty()) return;
  done.assign(values.size(), false);
  for (std::size_t start = 0; start < values.size(); ++start) {
    if (done[start]) continue;
    const T first = values[start];
    std::size_t j = start;
    while (order[j] != start) {
      values[j] = values[order[j]];
      done[j] = true;
      j = order[j];
    }
    values[j] = first;
    done[j] = true;
  }
}

}  // namespace

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
  // Attribute by attribute, in place: no copy of any of them (one bit a point marks what is done).
  std::vector<bool> done;
  permute(cloud.points, order, done);
  permute(cloud.normals, order, done);
  permute(cloud.colors, order, done);
  permute(cloud.intensities, order, done);
  for (ScalarField& f : cloud.scalars) permute(f.values, order, done);
}

}  // namespace ewis
