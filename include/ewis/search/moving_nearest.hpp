#pragma once
// Nearest neighbours of points that move a little between queries (ICP's source points from one iteration to the
// next): each point keeps the k target points that were nearest where it last was. They hold every target point
// nearer than the k-th (`radius`), so from a place `moved` away a candidate nearer than radius - moved is the
// nearest of all: the same answer as KdTree::nearest (ties by index, in the tree's arithmetic), from k distances
// instead of a search. Else the tree is searched and the list gathered again.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "ewis/search/kdtree.hpp"

namespace ewis {

class MovingNearest {
 public:
  // `ids`: the moving points it keeps lists for, increasing (52 bytes each; any other id is answered by the tree
  // alone). The tree must outlive this.
  MovingNearest(const KdTree& tree, std::vector<std::uint32_t> ids);
  // Keeps lists for `ids` (increasing) from now on: those of ids it kept already stay, the others start empty.
  void serve(std::vector<std::uint32_t> ids);
  // As tree.nearest(query, max_distance_mm, hint) for moving point `id` now at `query`. Calls for different ids
  // may run in parallel; calls for one id must not.
  Neighbor nearest(std::uint32_t id, const Eigen::Vector3f& query, float max_distance_mm, std::uint32_t hint);

 private:
  static constexpr std::uint32_t kList = 8;
  struct Entry {
    Eigen::Vector3f at = Eigen::Vector3f::Zero();
    float radius = 0;  // > 0: every target point nearer than this to `at` is in ids
    std::uint32_t count = 0;
    std::uint32_t ids[kList] = {};
  };
  const KdTree& tree_;
  std::vector<std::uint32_t> ids_;  // increasing; entries_[k] is ids_[k]'s
  std::vector<Entry> entries_;
};

}  // namespace ewis
