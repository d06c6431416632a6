// Batched k-d tree queries: one independent query per item, so the results cannot depend on the thread count.
#include "ewis/core/parallel.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis {

std::vector<Neighbor> nearest_batch(const KdTree& tree, const std::vector<Eigen::Vector3f>& queries) {
  std::vector<Neighbor> out(queries.size());
  parallel_for_each_index(queries.size(), [&](std::size_t i) { out[i] = tree.nearest(queries[i]); });
  return out;
}

std::vector<std::vector<Neighbor>> knn_batch(const KdTree& tree, const std::vector<Eigen::Vector3f>& queries, int k) {
  std::vector<std::vector<Neighbor>> out(queries.size());
  parallel_for_each_index(queries.size(), [&](std::size_t i) { tree.knn(queries[i], k, out[i]); });
  return out;
}

}  // namespace ewis
