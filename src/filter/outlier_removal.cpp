// Radius outlier removal (paper 4.1.1); the rule deriving r and k from the resolution is in the header.
#include "ewis/filter/outlier_removal.hpp"

#include <algorithm>
#include <cmath>

#include "ewis/core/parallel.hpp"
#include "ewis/filter/resolution.hpp"

namespace ewis {

RadiusOutlierResult remove_radius_outliers(const KdTree& tree, const RadiusOutlierParams& params) {
  RadiusOutlierResult result;
  const bool derive_r = !(params.radius_mm > 0);
  const bool derive_k = params.min_neighbors < 0;
  if (derive_r || derive_k) {
    const ResolutionResult res = spatial_resolution(tree, params.resolution_samples);
    // the median is robust to outliers; it is 0 only when most points are duplicates
    result.resolution_mm = res.median_mm > 0 ? res.median_mm : res.mean_mm;
  }
  const double R = result.resolution_mm;
  result.radius_mm = derive_r ? std::max(0.0, params.radius_factor) * R : params.radius_mm;
  if (derive_k) {
    int k = std::max(0, params.min_neighbors_floor);
    if (R > 0) {
      const double ratio = result.radius_mm / R;
      // bounded: ratios beyond 1000 would ask for more neighbours than any scan has
      const double expected = M_PI * std::min(ratio, 1000.0) * std::min(ratio, 1000.0);
      k = std::max<int>(k, static_cast<int>(std::lround(std::max(0.0, params.neighbor_fraction) * expected)));
    }
    result.min_neighbors = k;
  } else {
    result.min_neighbors = params.min_neighbors;
  }

  const std::size_t n = tree.size();
  if (result.min_neighbors == 0) {
    result.kept.resize(n);
    for (std::size_t i = 0; i < n; ++i) result.kept[i] = static_cast<std::uint32_t>(i);
    return result;
  }
  // the query point counts itself (distance 0), so k others means k + 1 points in the sphere
  const std::size_t need = static_cast<std::size_t>(result.min_neighbors) + 1;
  const float r = static_cast<float>(result.radius_mm);
  const auto& pts = tree.points();
  // queried in the tree's spatial order (cache locality), collected in index order
  const auto& order = tree.spatial_order();
  std::vector<std::uint8_t> keep(n, 0);
  parallel_blocks(order.size(), 2048, [&](std::size_t b, std::size_t e) {
    for (std::size_t j = b; j < e; ++j) keep[order[j]] = tree.count_within(pts[order[j]], r, need) >= need;
  });
  result.kept = parallel_select(n, [&](std::size_t i) { return keep[i] != 0; });
  return result;
}

}  // namespace ewis
