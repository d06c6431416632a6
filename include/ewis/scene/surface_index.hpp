#pragma once
// Exact closest-point queries on CAD triangles (a bounding-volume hierarchy over a chosen set of elements):
// the interference check measures gaps to the registered CAD surface of rigid elements (DESIGN.md
// "Measurement lessons": the sensor never sees the flanks that face each other, so point-based gaps read wide),
// and the registration's last step matches scan points to it (register/surface_refine.hpp).
#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "ewis/scene/scene.hpp"

namespace ewis {

struct SurfacePoint {
  double distance_mm = std::numeric_limits<double>::infinity();  // infinity: nothing within the limit
  std::int32_t element = -1;
  std::uint32_t triangle = 0;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // closest point on the surface
  bool found() const { return element >= 0; }
};

class SurfaceIndex {
 public:
  SurfaceIndex() = default;
  // Indexes the triangles of `elements` (scene element indices; empty list: nothing). The scene must outlive it.
  SurfaceIndex(const Scene& scene, const std::vector<int>& elements);

  bool empty() const { return nodes_.empty(); }
  // The scene elements indexed (as given, valid ones only, increasing).
  const std::vector<int>& elements() const { return elements_; }
  bool contains(int element) const { return std::binary_search(elements_.begin(), elements_.end(), element); }
  // Closest surface point within max_distance_mm (exact point-to-triangle distance). Thread-safe.
  SurfacePoint closest(const Eigen::Vector3d& p, double max_distance_mm = std::numeric_limits<double>::infinity()) const;
  // closest(points[i], max_distance_mm) for each of a few points near one another (e.g. consecutive points of a
  // cloud in leaf order) into out[i]: the same answers, the tree walked once for the group's box (a finite
  // max_distance_mm; else point by point). `leaves` is scratch, kept by the caller between calls.
  void closest_group(const Eigen::Vector3d* points, std::size_t n, double max_distance_mm, SurfacePoint* out,
                     std::vector<std::uint32_t>& leaves) const;
  // closest(point_at(i), max_distance_mm) for every i in [begin, end), handed to use(i, point, answer) in order;
  // runs of 16 consecutive points share one walk of the tree (closest_group), so consecutive points should lie near
  // one another (a cloud in leaf order).
  template <class PointAt, class Use>
  void closest_each(std::size_t begin, std::size_t end, double max_distance_mm, const PointAt& point_at,
                    const Use& use) const {
    SurfacePoint s[kRun];
    std::vector<std::uint32_t> leaves;
    in_runs(begin, end, point_at, [&](std::size_t i, const Eigen::Vector3d* p, std::size_t n) {
      closest_group(p, n, max_distance_mm, s, leaves);
      for (std::size_t j = 0; j < n; ++j) use(i + j, p[j], s[j]);
    });
  }
  // The element of closest(points[i], max_distance_mm) (-1: nothing within) for each of a few points near one
  // another, into out[i]: what closest_group answers, without the exact closest triangle where every triangle nearer
  // than a first one found (the last point's closest) is of that one's element (a point on a plate, away from its
  // edges). A finite max_distance_mm; else point by point.
  void closest_element_group(const Eigen::Vector3d* points, std::size_t n, double max_distance_mm, std::int32_t* out,
                             std::vector<std::uint32_t>& leaves) const;
  // closest_element_group over [begin, end) in runs of 16, handed to use(i, element) in order (as closest_each).
  template <class PointAt, class Use>
  void closest_element_each(std::size_t begin, std::size_t end, double max_distance_mm, const PointAt& point_at,
                            const Use& use) const {
    std::int32_t element[kRun];
    std::vector<std::uint32_t> leaves;
    in_runs(begin, end, point_at, [&](std::size_t i, const Eigen::Vector3d* p, std::size_t n) {
      closest_element_group(p, n, max_distance_mm, element, leaves);
      for (std::size_t j = 0; j < n; ++j) use(i + j, element[j]);
    });
  }
  // Least distance from the segment [a, b] to the surface, sampled every step_mm along the segment and refined
  // around the best sample (error far below step for smooth surfaces); infinity when beyond max_distance_mm.
  SurfacePoint closest_to_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double step_mm = 0.25,
                                  double max_distance_mm = std::numeric_limits<double>::infinity()) const;

 private:
  struct Node {
    Eigen::Vector3f lo = Eigen::Vector3f::Zero(), hi = Eigen::Vector3f::Zero();
    std::uint32_t first = 0, count = 0;  // leaf: triangles [first, first + count) of order_
    std::uint32_t left = 0, right = 0;   // inner node (count == 0)
    std::int32_t element = -1;           // leaf: the element of all its triangles (-1: of several)
  };
  const Scene* scene_ = nullptr;
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> order_;  // triangle indices
  std::vector<int> elements_;
  // Node `id` over triangles [first, first + count) of order_; its subtrees take the ids after it (left first).
  void build(std::uint32_t id, std::uint32_t first, std::uint32_t count, const std::vector<Eigen::Vector3f>& centroids,
             int depth);
  // The points point_at(i) for i in [begin, end) handed to group(first i, points, count) in runs of kRun.
  static constexpr std::size_t kRun = 16;
  template <class PointAt, class Group>
  static void in_runs(std::size_t begin, std::size_t end, const PointAt& point_at, const Group& group) {
    Eigen::Vector3d p[kRun];
    for (std::size_t i = begin; i < end; i += kRun) {
      const std::size_t n = std::min(kRun, end - i);
      for (std::size_t j = 0; j < n; ++j) p[j] = point_at(i + j);
      group(i, p, n);
    }
  }
  // closest_group's and closest_element_group's walk: per point the least (squared distance, triangle index) over the
  // group's leaves, the last point's triangle (the hint) first; with `by_element`, a point no other element's triangle
  // lies as near to as the hint takes the hint's answer (its element is the closest's; its distance is not set).
  // answer(i, best) for each point in order.
  template <class Answer>
  void group_walk(const Eigen::Vector3d* points, std::size_t n, double max_distance_mm, bool by_element,
                  std::vector<std::uint32_t>& leaves, const Answer& answer) const;
  // Whether no triangle of another element than best's lies within best_d2 of p (a tie included) in the leaves.
  bool settled_on(const Eigen::Vector3d& p, const std::vector<std::uint32_t>& leaves, double best_d2,
                  const SurfacePoint& best) const;
  // The leaves within max_distance_mm of the box of points[0, n) into `leaves`; false (none listed) when the distance
  // or a point is not finite.
  bool group_leaves(const Eigen::Vector3d* points, std::size_t n, double max_distance_mm,
                    std::vector<std::uint32_t>& leaves) const;
  // The least (squared distance, triangle index) over the listed leaves within best_d2 of p (after `best`).
  void closest_in_leaves(const Eigen::Vector3d& p, const std::vector<std::uint32_t>& leaves, double& best_d2,
                         SurfacePoint& best) const;
  // Triangle t against the best so far: the least (squared distance, triangle index) below best_d2 wins.
  void test_triangle(std::uint32_t t, const Eigen::Vector3d& p, double& best_d2, SurfacePoint& best) const;
};

// Closest point to p on triangle (a, b, c) (Ericson, Real-Time Collision Detection 5.1.5).
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c);

}  // namespace ewis
