#pragma once
// Euclidean clustering (as PCL's EuclideanClusterExtraction): the connected components of the graph that
// joins two points closer than a tolerance. Components outside [min_size, max_size] are dropped.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ewis/search/kdtree.hpp"

namespace ewis {

struct ClusterResult {
  // Each cluster's tree indices, increasing; clusters by size (largest first), then by smallest index.
  std::vector<std::vector<std::uint32_t>> clusters;
  std::size_t rejected_clusters = 0;  // components dropped for their size
  std::size_t rejected_points = 0;    // points in those components
};

// `subset` (tree indices) restricts the points clustered and the links between them; empty = all points.
// Two points are linked when their distance is <= tolerance_mm. Parallel (a lock-free union-find over
// one radius query per point); the components, hence the result, do not depend on the thread count.
ClusterResult euclidean_clusters(const KdTree& tree, const std::vector<std::uint32_t>& subset, double tolerance_mm,
                                 std::size_t min_size = 1, std::size_t max_size = static_cast<std::size_t>(-1));

}  // namespace ewis
