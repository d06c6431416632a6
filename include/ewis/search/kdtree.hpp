#pragma once
// k-d tree over a cloud's positions (nanoflann 1.4 inside; kept out of this header for compile times).
// The tree references `points`, which must outlive it and not change. Non-finite points (NaNs of organized
// scans) are never returned by a query; non-finite queries find nothing. All queries are thread-safe.
// Memory: the tree keeps a leaf-ordered copy of the finite points plus their indices (16 bytes per point).
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

namespace ewis {

// Slot j of the tree's leaf order holds the caller's point (*this)[j]; the identity when the tree uses the
// caller's points in place.
struct SpatialOrder {
  const std::uint32_t* ids = nullptr;  // null: the identity
  std::size_t count = 0;
  std::size_t size() const { return count; }
  std::uint32_t operator[](std::size_t j) const { return ids ? ids[j] : static_cast<std::uint32_t>(j); }
};

struct Neighbor {
  std::uint32_t index;
  float distance_sq;  // squared distance, mm^2
};

class KdTree {
 public:
  explicit KdTree(const std::vector<Eigen::Vector3f>& points);
  // Builds the tree and puts `points` into its leaf order by the same pass (the finite points in leaf order, then
  // the others in their order): the returned tree uses the permuted points in place (the same tree as a KdTree
  // built over them; identity spatial order), and `order` gets the permutation (new[j] = old[order[j]]) for the
  // caller's other attributes. The build moves a contiguous copy of the points, which then becomes `points` (the
  // caller's copy is freed before the build): 16 bytes a point and the nodes while it runs, no second build.
  static KdTree sorting(std::vector<Eigen::Vector3f>& points, std::vector<std::uint32_t>& order);
  ~KdTree();
  KdTree(KdTree&&) noexcept;
  KdTree& operator=(KdTree&&) noexcept;

  std::size_t size() const;
  const std::vector<Eigen::Vector3f>& points() const;
  // The indices of the finite points in the tree's leaf order (neighbours in space are neighbours here):
  // whole-cloud passes that query every point in this order hit the cache far more often.
  // Permuting a cloud by it (new[j] = old[order[j]]) puts the cloud into leaf order: a tree built over the
  // permuted points is the same tree and makes no copy.
  SpatialOrder spatial_order() const;

  // The k nearest points (fewer when the cloud is smaller), nearest first; ties by index.
  void knn(const Eigen::Vector3f& query, int k, std::vector<Neighbor>& out) const;
  // Nearest point; index -1 (as uint32 max) and infinite distance when the tree is empty.
  Neighbor nearest(const Eigen::Vector3f& query) const;
  // The same answer as nearest() when that lies within max_distance_mm (inclusive), else none (index -1):
  // found faster, the bound pruning the walk, and faster still from `hint`, the index of a point near the
  // answer (e.g. the answer to a nearby query, or to the same query before a small move; -1: none).
  Neighbor nearest(const Eigen::Vector3f& query, float max_distance_mm, std::uint32_t hint) const;
  // The squared distance from point `index` (the caller's) to `query` in the tree's own arithmetic: a caller
  // that picks among candidates by it (ties by index) picks what a search would.
  float distance_sq(std::uint32_t index, const Eigen::Vector3f& query) const;
  // All points within radius_mm (inclusive), sorted by distance then index.
  void radius(const Eigen::Vector3f& query, float radius_mm, std::vector<Neighbor>& out) const;
  // Number of points within radius_mm (inclusive), stopping early once `stop_at` are found.
  std::size_t count_within(const Eigen::Vector3f& query, float radius_mm, std::size_t stop_at) const;
  // All points within radius_mm (inclusive) in the tree's visiting order (deterministic, not sorted):
  // for callers that only need the set (clustering), it saves the sort.
  void radius_unsorted(const Eigen::Vector3f& query, float radius_mm, std::vector<Neighbor>& out) const;

 private:
  KdTree();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The bound to pass to nearest(query, bound, hint) when its answer is kept only within max_distance_mm by a test in
// double (or on a float squared distance): a hair wider, so that the float search never drops what that test keeps.
float search_bound_mm(double max_distance_mm);

// The tree's leaf order of the finite points (indices into `points`), computed with 4 bytes a point of extra
// memory (the tree itself copies the points): for permuting a cloud into leaf order (sort_for_search).
std::vector<std::uint32_t> spatial_sort_order(const std::vector<Eigen::Vector3f>& points);

// Batched queries in parallel; results independent of the thread count.
// For each query: nearest neighbour (index, squared distance).
std::vector<Neighbor> nearest_batch(const KdTree& tree, const std::vector<Eigen::Vector3f>& queries);
// For each query: its k nearest (fewer when the cloud is smaller), nearest first, ties by index.
std::vector<std::vector<Neighbor>> knn_batch(const KdTree& tree, const std::vector<Eigen::Vector3f>& queries, int k);

}  // namespace ewis
