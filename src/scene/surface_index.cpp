#include "ewis/scene/surface_index.hpp"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace ewis {

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) return a;  // degenerate triangle
  const double v = vb / denom, w = vc / denom;
  return a + ab * v + ac * w;
}

namespace {

// Nodes of the tree build() makes over n triangles: median splits down to leaves of at most 4. The sizes at one
// depth differ by at most one, so each depth holds at most two (size, how many) pairs.
std::size_t node_count(std::size_t n) {
  std::size_t nodes = 0;
  std::vector<std::pair<std::size_t, std::size_t>> level = {{n, 1}}, next;
  while (!level.empty()) {
    next.clear();
    const auto add = [&](std::size_t size, std::size_t k) {
      for (auto& [s, c] : next)
        if (s == size) return void(c += k);
      next.emplace_back(size, k);
    };
    for (const auto& [size, k] : level) {
      nodes += k;
      if (size > 4) add(size / 2, k), add(size - size / 2, k);
    }
    level.swap(next);
  }
  return nodes;
}

}  // namespace

SurfaceIndex::SurfaceIndex(const Scene& scene, const std::vector<int>& elements) : scene_(&scene) {
  for (int e : elements) {
    if (e < 0 || std::size_t(e) >= scene.elements.size()) continue;
    const Element& el = scene.elements[e];
    elements_.push_back(e);
    for (std::uint32_t t = el.first_triangle; t < el.first_triangle + el.triangle_count; ++t) order_.push_back(t);
  }
  std::sort(elements_.begin(), elements_.end());
  elements_.erase(std::unique(elements_.begin(), elements_.end()), elements_.end());
  if (order_.empty()) return;
  std::vector<Eigen::Vector3f> centroids(scene.triangles.size());
  for (std::uint32_t t : order_) {
    const auto& tri = scene.triangles[t];
    centroids[t] = (scene.vertices[tri[0]] + scene.vertices[tri[1]] + scene.vertices[tri[2]]) / 3.0f;
  }
  // Every node's place is known from the triangle counts (depth first, left before right), so the two halves of a
  // large node are built at once into their own ranges: the same tree as one at a time.
  nodes_.resize(node_count(order_.size()));
  build(0, 0, static_cast<std::uint32_t>(order_.size()), centroids, 0);
}

void SurfaceIndex::build(std::uint32_t id, std::uint32_t first, std::uint32_t count,
                         const std::vector<Eigen::Vector3f>& centroids, int depth) {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
  Eigen::Vector3f clo = lo, chi = hi;
  for (std::uint32_t i = first; i < first + count; ++i) {
    const auto& tri = scene_->triangles[order_[i]];
    for (int k = 0; k < 3; ++k) {
      lo = lo.cwiseMin(scene_->vertices[tri[k]]);
      hi = hi.cwiseMax(scene_->vertices[tri[k]]);
    }
    clo = clo.cwiseMin(centroids[order_[i]]);
    chi = chi.cwiseMax(centroids[order_[i]]);
  }
  nodes_[id].lo = lo;
  nodes_[id].hi = hi;
  if (count <= 4 || depth > 60) {  // (a leaf above the last level leaves its range's other slots unused)
    nodes_[id].first = first;
    nodes_[id].count = count;
    const std::int32_t e = static_cast<std::int32_t>(scene_->triangle_element[order_[first]]);
    nodes_[id].element = e;
    for (std::uint32_t i = first; i < first + count; ++i)
      if (static_cast<std::int32_t>(scene_->triangle_element[order_[i]]) != e) nodes_[id].element = -1;
    return;
  }
  int axis;
  (chi - clo).maxCoeff(&axis);
  const std::uint32_t mid = first + count / 2;
  // Median split by centroid; ties by triangle index keep the build deterministic.
  std::nth_element(order_.begin() + first, order_.begin() + mid, order_.begin() + first + count,
                   [&](std::uint32_t x, std::uint32_t y) {
                     const float cx = centroids[x][axis], cy = centroids[y][axis];
                     return cx < cy || (cx == cy && x < y);
                   });
  const std::uint32_t l = id + 1, r = l + static_cast<std::uint32_t>(node_count(mid - first));
  nodes_[id].left = l;
  nodes_[id].right = r;
  nodes_[id].count = 0;
  const auto left = [&] { build(l, first, mid - first, centroids, depth + 1); };
  const auto right = [&] { build(r, mid, first + count - mid, centroids, depth + 1); };
  if (count >= 8192) {
    tbb::parallel_invoke(left, right);
  } else {
    left();
    right();
  }
}

namespace {
double box_distance_sq(const Eigen::Vector3d& p, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double v = p[k] < lo[k] ? lo[k] - p[k] : (p[k] > hi[k] ? p[k] - hi[k] : 0.0);
    d2 += v * v;
  }
  return d2;
}
}  // namespace

SurfacePoint SurfaceIndex::closest(const Eigen::Vector3d& p, double max_distance_mm) const {
  SurfacePoint best;
  if (nodes_.empty() || !p.allFinite()) return best;
  double best_d2 = std::isfinite(max_distance_mm) ? max_distance_mm * max_distance_mm
                                                  : std::numeric_limits<double>::infinity();
  std::uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (box_distance_sq(p, n.lo, n.hi) > best_d2) continue;
    if (n.count > 0) {
      for (std::uint32_t i = n.first; i < n.first + n.count; ++i) test_triangle(order_[i], p, best_d2, best);
      continue;
    }
    // Nearer child last, so it is visited first.
    const double dl = box_distance_sq(p, nodes_[n.left].lo, nodes_[n.left].hi);
    const double dr = box_distance_sq(p, nodes_[n.right].lo, nodes_[n.right].hi);
    if (top + 2 > 128) continue;  // depth is bounded by the build (<= 61 levels); never hit
    if (dl <= dr) {
      stack[top++] = n.right;
      stack[top++] = n.left;
    } else {
      stack[top++] = n.left;
      stack[top++] = n.right;
    }
  }
  if (best.element >= 0) best.distance_mm = std::sqrt(best_d2);
  return best;
}

void SurfaceIndex::test_triangle(std::uint32_t t, const Eigen::Vector3d& p, double& best_d2, SurfacePoint& best) const {
  const auto& tri = scene_->triangles[t];
  const Eigen::Vector3d q = closest_point_on_triangle(p, scene_->vertices[tri[0]].cast<double>(),
                                                      scene_->vertices[tri[1]].cast<double>(),
                                                      scene_->vertices[tri[2]].cast<double>());
  const double d2 = (q - p).squaredNorm();
  if (d2 < best_d2 || (d2 == best_d2 && best.element >= 0 && t < best.triangle)) {
    best_d2 = d2;
    best.triangle = t;
    best.element = static_cast<std::int32_t>(scene_->triangle_element[t]);
    best.point = q;
  }
}

bool SurfaceIndex::group_leaves(const Eigen::Vector3d* points, std::size_t n, double max_distance_mm,
                                std::vector<std::uint32_t>& leaves) const {
  leaves.clear();
  bool finite = std::isfinite(max_distance_mm);
  Eigen::Vector3d glo = points[0], ghi = points[0];
  for (std::size_t i = 0; i < n; ++i) {
    finite = finite && points[i].allFinite();
    glo = glo.cwiseMin(points[i]);
    ghi = ghi.cwiseMax(points[i]);
  }
  if (!finite) return false;
  // Every leaf within the distance of the group's box: each point's answer lies in one of them (a hair of
  // slack keeps a box exactly at the distance).
  const double reach_sq = max_distance_mm * max_distance_mm * (1.0 + 1e-9);
  std::uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const std::uint32_t id = stack[--top];
    const Node& nd = nodes_[id];
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double v = std::max({double(nd.lo[k]) - ghi[k], glo[k] - double(nd.hi[k]), 0.0});
      d2 += v * v;
    }
    if (d2 > reach_sq) continue;
    if (nd.count > 0) {
      leaves.push_back(id);
    } else if (top + 2 <= 128) {
      stack[top++] = nd.right;
      stack[top++] = nd.left;
    }
  }
  return true;
}

void SurfaceIndex::closest_in_leaves(const Eigen::Vector3d& p, const std::vector<std::uint32_t>& leaves,
                                     double& best_d2, SurfacePoint& best) const {
  for (std::uint32_t id : leaves) {
    const Node& nd = nodes_[id];
    if (box_distance_sq(p, nd.lo, nd.hi) > best_d2) continue;
    for (std::uint32_t k = nd.first; k < nd.first + nd.count; ++k) test_triangle(order_[k], p, best_d2, best);
  }
}

bool SurfaceIndex::settled_on(const Eigen::Vector3d& p, const std::vector<std::uint32_t>& leaves, double best_d2,
                              const SurfacePoint& best) const {
  for (std::uint32_t id : leaves) {
    const Node& nd = nodes_[id];
    if (nd.element == best.element || box_distance_sq(p, nd.lo, nd.hi) > best_d2) continue;
    for (std::uint32_t k = nd.first; k < nd.first + nd.count; ++k) {
      const std::uint32_t t = order_[k];
      if (static_cast<std::int32_t>(scene_->triangle_element[t]) == best.element) continue;
      const auto& tri = scene_->triangles[t];
      const Eigen::Vector3d q = closest_point_on_triangle(p, scene_->vertices[tri[0]].cast<double>(),
                                                          scene_->vertices[tri[1]].cast<double>(),
                                                          scene_->vertices[tri[2]].cast<double>());
      if ((q - p).squaredNorm() <= best_d2) return false;
    }
  }
  return true;
}

template <class Answer>
void SurfaceIndex::group_walk(const Eigen::Vector3d* points, std::size_t n, double max_distance_mm, bool by_element,
                              std::vector<std::uint32_t>& leaves, const Answer& answer) const {
  if (n == 0) return;
  if (nodes_.empty() || !group_leaves(points, n, max_distance_mm, leaves)) {
    for (std::size_t i = 0; i < n; ++i) answer(i, closest(points[i], max_distance_mm));
    return;
  }
  // Per point, the same least (squared distance, triangle index) as closest(): the leaves it can reach in
  // turn, the last point's triangle first (its distance prunes most of them).
  std::uint32_t hint = std::numeric_limits<std::uint32_t>::max();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d& p = points[i];
    SurfacePoint best;
    double best_d2 = max_distance_mm * max_distance_mm;
    if (hint != std::numeric_limits<std::uint32_t>::max()) test_triangle(hint, p, best_d2, best);
    // (the hint's element is the answer's unless another element's triangle lies as near)
    if (!(by_element && best.element >= 0 && settled_on(p, leaves, best_d2, best))) {
      closest_in_leaves(p, leaves, best_d2, best);
      if (best.element >= 0) {
        best.distance_mm = std::sqrt(best_d2);
        hint = best.triangle;
      }
    }
    answer(i, best);
  }
}

void SurfaceIndex::closest_group(const Eigen::Vector3d* points, std::size_t n, double max_distance_mm,
                                 SurfacePoint* out, std::vector<std::uint32_t>& leaves) const {
  group_walk(points, n, max_distance_mm, false, leaves, [&](std::size_t i, const SurfacePoint& s) { out[i] = s; });
}

void SurfaceIndex::closest_element_group(const Eigen::Vector3d* points, std::size_t n, double max_distance_mm,
                                         std::int32_t* out, std::vector<std::uint32_t>& leaves) const {
  group_walk(points, n, max_distance_mm, true, leaves,
             [&](std::size_t i, const SurfacePoint& s) { out[i] = s.element; });
}

SurfacePoint SurfaceIndex::closest_to_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double step_mm,
                                              double max_distance_mm) const {
  SurfacePoint best;
  if (nodes_.empty()) return best;
  const double len = (b - a).norm();
  const int n = std::clamp(int(std::ceil(len / std::max(step_mm, 1e-3))), 1, 100000);
  double limit = max_distance_mm;
  int best_i = -1;
  for (int i = 0; i <= n; ++i) {
    const Eigen::Vector3d p = a + (b - a) * (double(i) / n);
    const SurfacePoint s = closest(p, limit);
    if (s.found() && s.distance_mm < best.distance_mm) {
      best = s;
      best_i = i;
      limit = s.distance_mm;
    }
  }
  if (best_i < 0) return best;
  // Golden-section refinement on the bracket around the best sample (the distance is unimodal there).
  double lo = std::max(0.0, double(best_i - 1) / n), hi = std::min(1.0, double(best_i + 1) / n);
  const double g = (std::sqrt(5.0) - 1) / 2;
  for (int it = 0; it < 30 && hi - lo > 1e-6; ++it) {
    const double t1 = hi - g * (hi - lo), t2 = lo + g * (hi - lo);
    const SurfacePoint s1 = closest(a + (b - a) * t1), s2 = closest(a + (b - a) * t2);
    if (s1.distance_mm < best.distance_mm) best = s1;
    if (s2.distance_mm < best.distance_mm) best = s2;
    if (s1.distance_mm <= s2.distance_mm) hi = t2;
    else lo = t1;
  }
  return best;
}

}  // namespace ewis
