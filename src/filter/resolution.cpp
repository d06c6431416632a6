// Spatial resolution R(PC) (paper 4.1.1): mean distance from each point to its nearest other point.
#include "ewis/filter/resolution.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ewis/core/parallel.hpp"

namespace ewis {
namespace {

// Distance to the nearest OTHER point: the two nearest by (distance, index) always hold one point that is
// not the query itself, and a duplicate (another index at distance 0) counts as 0.
float nearest_other_mm(const KdTree& tree, std::uint32_t i, std::vector<Neighbor>& scratch) {
  tree.knn(tree.points()[i], 2, scratch);
  for (const Neighbor& nb : scratch)
    if (nb.index != i) return std::sqrt(nb.distance_sq);
  return std::numeric_limits<float>::quiet_NaN();  // non-finite point or a cloud of one
}

struct SumCount {
  double sum = 0.0;
  std::size_t count = 0;
};

}  // namespace

ResolutionResult spatial_resolution(const KdTree& tree, std::size_t max_samples) {
  ResolutionResult result;
  const std::size_t n = tree.size();
  if (n < 2) return result;
  const std::size_t stride = (max_samples > 0 && max_samples < n) ? (n + max_samples - 1) / max_samples : 1;
  const std::size_t samples = (n + stride - 1) / stride;

  // Queried in the tree's spatial order for cache locality; each sample's distance lands in its own slot,
  // so the order of the queries cannot change the result. Non-finite points stay NaN and are skipped.
  std::vector<float> dist(samples, std::numeric_limits<float>::quiet_NaN());
  const auto& order = tree.spatial_order();
  parallel_blocks(order.size(), 2048, [&](std::size_t b, std::size_t e) {
    std::vector<Neighbor> scratch;
    scratch.reserve(2);
    for (std::size_t j = b; j < e; ++j) {
      const std::uint32_t i = order[j];
      if (i % stride == 0) dist[i / stride] = nearest_other_mm(tree, i, scratch);
    }
  });

  // Sums in fixed blocks combined in block order: the same bits for any thread count.
  const SumCount total = parallel_reduce_ordered(
      samples, 8192, SumCount{},
      [&](std::size_t b, std::size_t e) {
        SumCount sc;
        for (std::size_t s = b; s < e; ++s)
          if (std::isfinite(dist[s])) {
            sc.sum += dist[s];
            ++sc.count;
          }
        return sc;
      },
      [](SumCount a, const SumCount& b) {
        a.sum += b.sum;
        a.count += b.count;
        return a;
      });
  if (total.count == 0) return result;

  dist.erase(std::remove_if(dist.begin(), dist.end(), [](float d) { return !std::isfinite(d); }), dist.end());
  const std::size_t m = dist.size();
  auto mid = dist.begin() + static_cast<std::ptrdiff_t>(m / 2);
  std::nth_element(dist.begin(), mid, dist.end());
  double median = *mid;
  if (m % 2 == 0) median = 0.5 * (median + *std::max_element(dist.begin(), mid));

  result.mean_mm = total.sum / static_cast<double>(total.count);
  result.median_mm = median;
  result.points = total.count;
  return result;
}

}  // namespace ewis
