// Euclidean clustering by a concurrent union-find: every point links to its neighbours within the tolerance.
// The union always hangs the larger root under the smaller one, so each root is its component's smallest
// index whatever the order of the unions: the components are the same for any thread count.
#include "ewis/filter/euclidean_clusters.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>

#include "ewis/core/parallel.hpp"

namespace ewis {
namespace {

class ConcurrentUnionFind {
 public:
  explicit ConcurrentUnionFind(std::size_t n) : parent_(new std::atomic<std::uint32_t>[n]) {
    for (std::size_t i = 0; i < n; ++i) parent_[i].store(static_cast<std::uint32_t>(i), std::memory_order_relaxed);
  }

  // Parents only ever decrease (each step moves to a smaller index), so every loop here ends.
  std::uint32_t find(std::uint32_t x) const {
    for (;;) {
      const std::uint32_t p = parent_[x].load(std::memory_order_relaxed);
      if (p == x) return x;
      const std::uint32_t gp = parent_[p].load(std::memory_order_relaxed);
      // path halving; a lost race only means less compression
      if (gp != p) {
        std::uint32_t expected = p;
        parent_[x].compare_exchange_weak(expected, gp, std::memory_order_relaxed);
      }
      x = gp;
    }
  }

  void unite(std::uint32_t a, std::uint32_t b) {
    for (;;) {
      a = find(a);
      b = find(b);
      if (a == b) return;
      if (a > b) std::swap(a, b);
      std::uint32_t expected = b;  // b is still a root: hang it under the smaller root a
      if (parent_[b].compare_exchange_strong(expected, a, std::memory_order_acq_rel)) return;
    }
  }

 private:
  std::unique_ptr<std::atomic<std::uint32_t>[]> parent_;
};

}  // namespace

ClusterResult euclidean_clusters(const KdTree& tree, const std::vector<std::uint32_t>& subset, double tolerance_mm,
                                 std::size_t min_size, std::size_t max_size) {
  ClusterResult result;
  const std::size_t n = tree.size();
  if (n == 0 || n > std::numeric_limits<std::uint32_t>::max()) return result;

  // members: the points clustered (a subset may hold repeats or out-of-range indices: ignore them;
  // non-finite points belong to no cluster)
  const auto& pts = tree.points();
  std::vector<std::uint32_t> order;  // the members, increasing; the union-find works on their slots in it
  // A subset of at most 1/8 of the cloud is handled in memory proportional to it (binary search for a
  // neighbour's slot), so clustering a few thousand points of a million-point cloud costs no per-cloud
  // arrays (issue 8: inspect's peak memory).
  const bool compact = !subset.empty() && subset.size() <= n / 8;
  std::vector<std::uint8_t> member;
  if (compact) {
    order.reserve(subset.size());
    for (std::uint32_t i : subset)
      if (i < n && pts[i].allFinite()) order.push_back(i);
    std::sort(order.begin(), order.end());
    order.erase(std::unique(order.begin(), order.end()), order.end());
  } else {
    member.assign(n, subset.empty() ? 1 : 0);
    for (std::uint32_t i : subset)
      if (i < n) member[i] = 1;
    for (std::size_t i = 0; i < n; ++i)
      if (member[i] && !pts[i].allFinite()) member[i] = 0;
    order.reserve(subset.empty() ? n : subset.size());
    for (std::size_t i = 0; i < n; ++i)
      if (member[i]) order.push_back(static_cast<std::uint32_t>(i));
  }
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  // slot of point i in `order`, kNone when i is not a member
  auto slot_of = [&](std::uint32_t i) -> std::uint32_t {
    if (!compact) return member[i] ? i : kNone;
    const auto it = std::lower_bound(order.begin(), order.end(), i);
    return it != order.end() && *it == i ? static_cast<std::uint32_t>(it - order.begin()) : kNone;
  };
  // Union-find over point indices (whole cloud) or slots (compact); both orders follow the point index, so a
  // root is always its component's smallest member.
  ConcurrentUnionFind uf(compact ? order.size() : n);
  const float tol = tolerance_mm > 0 ? static_cast<float>(tolerance_mm) : 0.0f;
  auto link = [&](std::uint32_t i, std::uint32_t key, std::vector<Neighbor>& nb) {
    tree.radius_unsorted(pts[i], tol, nb);
    // each pair is seen from both ends: link from the larger index only
    for (const Neighbor& q : nb)
      if (q.index < i) {
        const std::uint32_t other = slot_of(q.index);
        if (other != kNone) uf.unite(key, other);
      }
  };
  if (compact) {
    parallel_blocks(order.size(), 256, [&](std::size_t b, std::size_t e) {
      std::vector<Neighbor> nb;
      for (std::size_t j = b; j < e; ++j) link(order[j], static_cast<std::uint32_t>(j), nb);
    });
  } else {
    // queries in the tree's spatial order (cache locality); the components do not depend on the order
    const auto& spatial = tree.spatial_order();
    parallel_blocks(spatial.size(), 1024, [&](std::size_t b, std::size_t e) {
      std::vector<Neighbor> nb;
      for (std::size_t j = b; j < e; ++j) {
        const std::uint32_t i = spatial[j];
        if (member[i]) link(i, i, nb);
      }
    });
  }

  // Roots are the smallest member of each component; group in increasing index order.
  std::vector<std::uint32_t> root(order.size());
  parallel_for_each_index(order.size(), [&](std::size_t j) {
    root[j] = uf.find(compact ? static_cast<std::uint32_t>(j) : order[j]);
  });
  // Component ids in order of first appearance = order of smallest index; sizes first, so that the many
  // one-point components of an outlier-rich scan cost no allocation.
  std::vector<std::uint32_t> slot(compact ? order.size() : n, kNone);
  std::vector<std::uint32_t> sizes;
  for (std::size_t j = 0; j < order.size(); ++j) {
    std::uint32_t& s = slot[root[j]];
    if (s == kNone) {
      s = static_cast<std::uint32_t>(sizes.size());
      sizes.push_back(0);
    }
    ++sizes[s];
  }
  std::vector<std::uint32_t> out_of(sizes.size(), kNone);
  for (std::size_t c = 0; c < sizes.size(); ++c) {
    if (sizes[c] >= min_size && sizes[c] <= max_size) {
      out_of[c] = static_cast<std::uint32_t>(result.clusters.size());
      result.clusters.emplace_back();
      result.clusters.back().reserve(sizes[c]);
    } else {
      ++result.rejected_clusters;
      result.rejected_points += sizes[c];
    }
  }
  for (std::size_t j = 0; j < order.size(); ++j) {
    const std::uint32_t c = out_of[slot[root[j]]];
    if (c != kNone) result.clusters[c].push_back(order[j]);
  }
  // components were created in order of their smallest index; a stable sort by size keeps that as tiebreak
  std::stable_sort(result.clusters.begin(), result.clusters.end(),
                   [](const auto& a, const auto& b) { return a.size() > b.size(); });
  return result;
}

}  // namespace ewis
