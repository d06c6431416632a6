// k-d tree over a cloud's positions, our own (DESIGN.md "Search"): an implicit balanced tree whose leaves are
// contiguous runs of the points in leaf order. Memory is the leaf-ordered copy and its index map (16 bytes a
// point) plus 12 bytes per 8-16 points of split planes; nothing at all besides the planes when the caller's
// points are already in leaf order (`spatial_order()` is then the identity, see kdtree.hpp). nanoflann 1.4,
// which this replaces, needed 30 bytes a point (its index array and 32-byte nodes on top of the copy).
// Queries walk the tree like nanoflann's: the nearer child first, the farther one only when the squared
// distance to its half-space (accumulated per axis) can still beat the result set's worst distance.
#include "ewis/search/kdtree.hpp"

#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <utility>

namespace ewis {
namespace {

// Leaves hold kLeafSize / 2 to kLeafSize points (every leaf is at the same depth; sizes differ by at most one).
// 16 was measured against 8, 12 and 24 on the 1.3 M-point compare scan (build, radius counts, 16-NN).
constexpr std::size_t kLeafSize = 12;
// Subtrees with fewer points than this are built on the calling thread.
constexpr std::size_t kParallelBuildMin = 65536;

// A point is added when dist < worstDist(); the next float up makes a radius inclusive.
// (Bit increment = nextafter towards +inf for finite non-negative floats, without a libm call.)
inline float inclusive(float radius_sq) {
  if (!(radius_sq >= 0) || !std::isfinite(radius_sq)) return radius_sq;
  return std::bit_cast<float>(std::bit_cast<std::uint32_t>(radius_sq) + 1u);
}

bool is_finite(const Eigen::Vector3f& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()); }

// Squared distance with the arithmetic of nanoflann's L2_Simple_Adaptor ((0 + dx^2) + dy^2) + dz^2, so results
// are bit-identical to the tests' brute force.
inline float dist_sq(const Eigen::Vector3f& p, const float* q) {
  const float dx = p[0] - q[0];
  const float dy = p[1] - q[1];
  const float dz = p[2] - q[2];
  float d = dx * dx;
  d += dy * dy;
  d += dz * dz;
  return d;
}

// The k nearest by (distance, index): deterministic whatever order the tree visits the points in.
class KnnSet {
 public:
  KnnSet(Neighbor* buf, std::size_t k, const std::uint32_t* ids) : buf_(buf), k_(k), ids_(ids) {}
  std::size_t size() const { return count_; }
  // while full, a point at exactly the k-th distance may still win on its smaller index
  float worstDist() const { return worst_; }
  // Nothing farther than sqrt(distance_sq) can enter (on an empty set).
  void bound(float distance_sq) { worst_ = std::min(worst_, inclusive(distance_sq)); }
  // A point known before the search (its caller's index): the search then only visits what can beat it.
  void seed(std::uint32_t index, float d) {
    buf_[0] = {index, d};
    count_ = 1;
    if (count_ == k_) worst_ = inclusive(d);
  }
  bool addPoint(float d, std::uint32_t slot) {
    const std::uint32_t idx = ids_ ? ids_[slot] : slot;  // ties compare the caller's indices
    auto less = [](float da, std::uint32_t ia, const Neighbor& b) {
      return da < b.distance_sq || (da == b.distance_sq && ia < b.index);
    };
    const bool full = count_ == k_;
    if (full && !less(d, idx, buf_[k_ - 1])) return true;
    if (!full) ++count_;
    std::size_t i = count_ - 1;
    while (i > 0 && less(d, idx, buf_[i - 1])) {
      buf_[i] = buf_[i - 1];
      --i;
    }
    buf_[i] = {idx, d};
    if (count_ == k_) worst_ = inclusive(buf_[k_ - 1].distance_sq);
    return true;
  }

 private:
  Neighbor* buf_;
  std::size_t k_;
  const std::uint32_t* ids_;
  std::size_t count_ = 0;
  float worst_ = std::numeric_limits<float>::infinity();
};

class RadiusSet {
 public:
  RadiusSet(float radius_sq, std::vector<Neighbor>& out, const std::uint32_t* ids)
      : worst_(inclusive(radius_sq)), out_(out), ids_(ids) {}
  float worstDist() const { return worst_; }
  bool addPoint(float d, std::uint32_t slot) {
    out_.push_back({ids_ ? ids_[slot] : slot, d});
    return true;
  }

 private:
  float worst_;
  std::vector<Neighbor>& out_;
  const std::uint32_t* ids_;
};

// DESIGN.md: "radius counts stop at the count they need"; returning false from addPoint ends the search.
class CountSet {
 public:
  CountSet(float radius_sq, std::size_t stop_at) : worst_(inclusive(radius_sq)), stop_at_(stop_at) {}
  std::size_t size() const { return count_; }
  float worstDist() const { return worst_; }
  bool addPoint(float, std::uint32_t) { return ++count_ < stop_at_; }

 private:
  float worst_;
  std::size_t stop_at_;
  std::size_t count_ = 0;
};

// A node in preorder (the left child of node k is k + 1), 12 bytes. Inner nodes: the left child's points have
// coordinate `dim` <= low, the right child's >= high (low <= high). Leaves (dim == 3): slots [begin, end).
struct Node {
  std::uint32_t a;              // low (float bits), or begin
  std::uint32_t b;              // high (float bits), or end
  std::uint32_t right_and_dim;  // index of the right child << 2 | dim
  std::uint32_t dim() const { return right_and_dim & 3u; }
  std::uint32_t right() const { return right_and_dim >> 2; }
  float low() const { return std::bit_cast<float>(a); }
  float high() const { return std::bit_cast<float>(b); }
};
constexpr std::uint32_t kLeaf = 3;

struct Box {
  Eigen::Vector3f lo;
  Eigen::Vector3f hi;
};

Box bounds_of(const Eigen::Vector3f* p, std::size_t b, std::size_t e) {
  Box box{p[b], p[b]};
  for (std::size_t i = b + 1; i < e; ++i) {
    box.lo = box.lo.cwiseMin(p[i]);
    box.hi = box.hi.cwiseMax(p[i]);
  }
  return box;
}

}  // namespace

struct KdTree::Impl {
  const std::vector<Eigen::Vector3f>* points = nullptr;
  // The finite points in leaf order and, per slot, the caller's index. Both stay empty when the caller's
  // points are already in leaf order with every finite point before any non-finite one (slot == index).
  std::vector<Eigen::Vector3f> sorted;
  std::vector<std::uint32_t> ids;
  const Eigen::Vector3f* pts = nullptr;  // slot -> position
  std::size_t count = 0;                 // finite points (slots)
  std::vector<Node> nodes;               // preorder; node 0 is the root
  Box box{};                             // bounds of all finite points
  const std::uint32_t* id_map() const { return ids.empty() ? nullptr : ids.data(); }

  // The nodes over the `count` finite points at `moved` by the copying build, which moves them and their caller's
  // indices `ids` together into leaf order; sets `box`.
  void build_moving(Eigen::Vector3f* moved, std::uint32_t* ids);
  // About 0.3 nodes a point on scans (measured: 375 k for 1.27 M points); give back a large excess only.
  void trim_nodes() {
    if (nodes.capacity() > nodes.size() + nodes.size() / 8) nodes.shrink_to_fit();
  }

  template <class Set>
  bool search(Set& set, const float* q, const Node* node, float mindist, float* dists) const;
  template <class Set>
  void find(Set& set, const Eigen::Vector3f& query) const;
};

namespace {

// Builds the nodes over slots [b, e) with nanoflann's rule (its middleSplit_, which keeps cells close to cubes
// on surfaces with outliers around them, where a median split was measured 10-20% slower to query): cut the
// widest side of the cell box (among sides within 1e-5 of the widest, the one with the widest spread of the
// points) at its middle, clamped to the points' range; the points below go left, those above right, and
// points on the plane fill the smaller side up to half. Modes: InPlace reads the caller's points and may move
// nothing (the build fails at the first split that would move a point, and the caller copies and builds
// again); Copy moves a copy of the points and their indices; Gather moves only the indices and reads the
// caller's points through them (4 bytes a point, for sort_for_search, slower from the scattered reads).
enum class BuildMode { InPlace, Copy, Gather };

template <BuildMode Mode>
class Builder {
 public:
  Builder(const Eigen::Vector3f* pts, Eigen::Vector3f* sorted, std::uint32_t* ids)
      : pts_(pts), sorted_(sorted), ids_(ids) {}
  bool failed() const { return failed_.load(std::memory_order_relaxed); }

  // Appends the subtree's nodes to `out` (indices relative to out's start + `base`); `box` is the cell on
  // entry and the points' exact bounds on return.
  void build(std::vector<Node>& out, std::size_t base, std::size_t b, std::size_t e, Box& box) {
    if (failed()) return;
    const std::size_t k = out.size();
    if constexpr (kNodes) out.push_back({static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(e), kLeaf});
    const std::size_t n = e - b;
    if (n <= kLeafSize) {
      box = {P(b), P(b)};
      for (std::size_t i = b + 1; i < e; ++i) {
        box.lo = box.lo.cwiseMin(P(i));
        box.hi = box.hi.cwiseMax(P(i));
      }
      return;
    }
    // the side to cut
    const Eigen::Vector3f span = box.hi - box.lo;
    const float max_span = span.maxCoeff();
    int dim = 0;
    float max_spread = -1, cut_min = 0, cut_max = 0;
    for (int d = 0; d < 3; ++d) {
      if (!(span[d] > (1 - 1e-5f) * max_span)) continue;
      float lo = P(b)[d], hi = lo;
      for (std::size_t i = b + 1; i < e; ++i) {
        lo = std::min(lo, P(i)[d]);
        hi = std::max(hi, P(i)[d]);
      }
      if (hi - lo > max_spread) {
        dim = d;
        max_spread = hi - lo;
        cut_min = lo;
        cut_max = hi;
      }
    }
    const float middle = (box.lo[dim] + box.hi[dim]) / 2;
    const float cut = std::clamp(middle, cut_min, cut_max);
    std::size_t below = 0, at_or_below = 0;
    for (std::size_t i = b; i < e; ++i) {
      below += P(i)[dim] < cut;
      at_or_below += P(i)[dim] <= cut;
    }
    const std::size_t size_left = below > n / 2 ? below : at_or_below < n / 2 ? at_or_below : n / 2;
    const std::size_t m = b + size_left;
    bool split = true;
    for (std::size_t i = b; i < m && split; ++i) split = P(i)[dim] <= cut;
    for (std::size_t i = m; i < e && split; ++i) split = P(i)[dim] >= cut;
    if (!split) {
      if constexpr (Mode == BuildMode::InPlace) {
        failed_.store(true, std::memory_order_relaxed);
        return;
      }
      partition(b, e, dim, cut);  // [< cut][== cut][> cut]: below | at | above, so m is a valid split
    }
    Box left = box, right = box;
    left.hi[dim] = cut;
    right.lo[dim] = cut;
    if (n >= kParallelBuildMin) {
      // the left subtree goes on in `out`; the right one is built apart and appended (copying only it)
      std::vector<Node> right_nodes;
      tbb::task_group g;
      g.run([&] { build(right_nodes, 0, m, e, right); });
      build(out, base, b, m, left);
      g.wait();
      if (failed()) return;
      if constexpr (kNodes) {
        out[k].right_and_dim = static_cast<std::uint32_t>((base + out.size()) << 2) | dim;
        append(out, right_nodes, base + out.size());
      }
    } else {
      build(out, base, b, m, left);
      if (failed()) return;
      if constexpr (kNodes) out[k].right_and_dim = static_cast<std::uint32_t>((base + out.size()) << 2) | dim;
      build(out, base, m, e, right);
      if (failed()) return;
    }
    if constexpr (kNodes) {
      out[k].a = std::bit_cast<std::uint32_t>(left.hi[dim]);
      out[k].b = std::bit_cast<std::uint32_t>(right.lo[dim]);
    }
    box.lo = left.lo.cwiseMin(right.lo);
    box.hi = left.hi.cwiseMax(right.hi);
  }

 private:
  static constexpr bool kNodes = Mode != BuildMode::Gather;  // the order alone needs no nodes

  const Eigen::Vector3f& P(std::size_t slot) const {
    if constexpr (Mode == BuildMode::Gather) return pts_[ids_[slot]];
    else return pts_[slot];
  }

  // nodes built apart start at index 0: shift their right-child links to where they land
  static void append(std::vector<Node>& out, const std::vector<Node>& sub, std::size_t at) {
    for (Node nd : sub) {
      if (nd.dim() != kLeaf) nd.right_and_dim += static_cast<std::uint32_t>(at << 2);
      out.push_back(nd);
    }
  }

  void swap_slots(std::size_t i, std::size_t j) {
    if constexpr (Mode == BuildMode::Copy) std::swap(sorted_[i], sorted_[j]);
    std::swap(ids_[i], ids_[j]);
  }

  // Two passes of nanoflann's planeSplit: first the points < cut to the front, then those == cut after them.
  void partition(std::size_t b, std::size_t e, int dim, float cut) {
    auto pass = [&](std::size_t lo, auto goes_left) {
      std::size_t hi = e;
      while (true) {
        while (lo < hi && goes_left(P(lo)[dim])) ++lo;
        while (lo < hi && !goes_left(P(hi - 1)[dim])) --hi;
        if (hi - lo < 2) return lo;
        swap_slots(lo, hi - 1);
        ++lo;
        --hi;
      }
    };
    const std::size_t at = pass(b, [cut](float v) { return v < cut; });
    pass(at, [cut](float v) { return v <= cut; });
  }

  const Eigen::Vector3f* pts_;
  Eigen::Vector3f* sorted_;
  std::uint32_t* ids_;
  std::atomic<bool> failed_{false};
};

}  // namespace

void KdTree::Impl::build_moving(Eigen::Vector3f* moved, std::uint32_t* ids) {
  box = bounds_of(moved, 0, count);
  Box cell = box;
  Builder<BuildMode::Copy> builder(moved, moved, ids);
  builder.build(nodes, 0, 0, count, cell);
}

template <class Set>
bool KdTree::Impl::search(Set& set, const float* q, const Node* nd, float mindist, float* dists) const {
  const std::uint32_t dim = nd->dim();
  if (dim == kLeaf) {
    float worst = set.worstDist();
    for (std::uint32_t s = nd->a; s < nd->b; ++s) {
      const float d = dist_sq(pts[s], q);
      if (d < worst) {
        if (!set.addPoint(d, s)) return false;
        worst = set.worstDist();
      }
    }
    return true;
  }
  const float val = q[dim];
  const float diff1 = val - nd->low();
  const float diff2 = val - nd->high();
  const Node* left = nd + 1;
  const Node* right = nodes.data() + nd->right();
  const Node* best = left;
  const Node* other = right;
  float cut = diff2 * diff2;
  if (diff1 + diff2 >= 0) {
    best = right;
    other = left;
    cut = diff1 * diff1;
  }
  if (!search(set, q, best, mindist, dists)) return false;
  const float saved = dists[dim];
  mindist = mindist + cut - saved;
  dists[dim] = cut;
  if (mindist <= set.worstDist() && !search(set, q, other, mindist, dists)) return false;
  dists[dim] = saved;
  return true;
}

template <class Set>
void KdTree::Impl::find(Set& set, const Eigen::Vector3f& query) const {
  if (count == 0) return;
  const float* q = query.data();
  float dists[3] = {0, 0, 0};
  float mindist = 0;
  for (int d = 0; d < 3; ++d) {
    if (q[d] < box.lo[d]) dists[d] = (q[d] - box.lo[d]) * (q[d] - box.lo[d]);
    else if (q[d] > box.hi[d]) dists[d] = (q[d] - box.hi[d]) * (q[d] - box.hi[d]);
    mindist += dists[d];
  }
  search(set, q, nodes.data(), mindist, dists);
}

KdTree::KdTree(const std::vector<Eigen::Vector3f>& points) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.points = &points;
  std::size_t finite = 0;
  for (const auto& p : points) finite += is_finite(p);
  m.count = finite;
  if (finite == 0) return;
  m.nodes.reserve(finite / 3 + 64);

  // First over the caller's points in place: when they are already in leaf order no split moves anything and
  // no copy is made. Otherwise (the first split that would move a point stops it) over a copy.
  bool in_place = true;
  for (std::size_t i = 0; i < finite && in_place; ++i) in_place = is_finite(points[i]);
  if (in_place) {
    m.pts = points.data();
    m.box = bounds_of(m.pts, 0, finite);
    Box box = m.box;
    Builder<BuildMode::InPlace> builder(m.pts, nullptr, nullptr);
    builder.build(m.nodes, 0, 0, finite, box);
    in_place = !builder.failed();
  }
  if (!in_place) {
    m.nodes.clear();
    m.sorted.reserve(finite);
    m.ids.reserve(finite);
    for (std::size_t i = 0; i < points.size(); ++i)
      if (is_finite(points[i])) {
        m.sorted.push_back(points[i]);
        m.ids.push_back(static_cast<std::uint32_t>(i));
      }
    m.pts = m.sorted.data();
    m.build_moving(m.sorted.data(), m.ids.data());
  }
  m.trim_nodes();
}

KdTree::KdTree() : impl_(std::make_unique<Impl>()) {}

KdTree KdTree::sorting(std::vector<Eigen::Vector3f>& points, std::vector<std::uint32_t>& order) {
  KdTree tree;
  Impl& m = *tree.impl_;
  std::vector<Eigen::Vector3f> sorted, others;
  sorted.reserve(points.size());
  order.clear();
  order.reserve(points.size());
  std::vector<std::uint32_t> other_ids;  // the non-finite points, which go last in their order
  for (std::size_t i = 0; i < points.size(); ++i)
    if (is_finite(points[i])) {
      sorted.push_back(points[i]);
      order.push_back(static_cast<std::uint32_t>(i));
    } else {
      others.push_back(points[i]);
      other_ids.push_back(static_cast<std::uint32_t>(i));
    }
  // The caller's positions are copied: freed before the build, so that its nodes do not add to their two copies.
  std::vector<Eigen::Vector3f>().swap(points);
  m.count = sorted.size();
  if (m.count > 0) {
    // the constructor's copying build, whose moved copy and index map are the sorted points and the order
    m.nodes.reserve(m.count / 3 + 64);
    m.build_moving(sorted.data(), order.data());
    m.trim_nodes();
  }
  sorted.insert(sorted.end(), others.begin(), others.end());
  order.insert(order.end(), other_ids.begin(), other_ids.end());
  points.swap(sorted);
  m.points = &points;
  m.pts = points.data();
  return tree;
}

std::vector<std::uint32_t> spatial_sort_order(const std::vector<Eigen::Vector3f>& points) {
  std::vector<std::uint32_t> ids;
  ids.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    if (is_finite(points[i])) ids.push_back(static_cast<std::uint32_t>(i));
  if (ids.empty()) return ids;
  Box box{points[ids[0]], points[ids[0]]};
  for (std::uint32_t i : ids) {
    box.lo = box.lo.cwiseMin(points[i]);
    box.hi = box.hi.cwiseMax(points[i]);
  }
  std::vector<Node> nodes;
  Builder<BuildMode::Gather> builder(points.data(), nullptr, ids.data());
  builder.build(nodes, 0, 0, ids.size(), box);
  return ids;
}

KdTree::~KdTree() = default;
KdTree::KdTree(KdTree&&) noexcept = default;
KdTree& KdTree::operator=(KdTree&&) noexcept = default;

std::size_t KdTree::size() const { return impl_ ? impl_->points->size() : 0; }

SpatialOrder KdTree::spatial_order() const {
  if (!impl_) return {nullptr, 0};
  return {impl_->id_map(), impl_->count};
}

const std::vector<Eigen::Vector3f>& KdTree::points() const { return *impl_->points; }

void KdTree::knn(const Eigen::Vector3f& query, int k, std::vector<Neighbor>& out) const {
  out.clear();
  if (!impl_ || impl_->count == 0 || k <= 0 || !is_finite(query)) return;
  const std::size_t kk = std::min<std::size_t>(static_cast<std::size_t>(k), impl_->count);
  out.resize(kk);
  KnnSet set(out.data(), kk, impl_->id_map());
  impl_->find(set, query);
  out.resize(set.size());
}

Neighbor KdTree::nearest(const Eigen::Vector3f& query) const {
  return nearest(query, std::numeric_limits<float>::infinity(), std::numeric_limits<std::uint32_t>::max());
}

Neighbor KdTree::nearest(const Eigen::Vector3f& query, float max_distance_mm, std::uint32_t hint) const {
  Neighbor best{std::numeric_limits<std::uint32_t>::max(), std::numeric_limits<float>::infinity()};
  if (!impl_ || impl_->count == 0 || !is_finite(query) || !(max_distance_mm >= 0)) return best;
  const float max_sq = max_distance_mm * max_distance_mm;
  KnnSet set(&best, 1, impl_->id_map());
  const std::vector<Eigen::Vector3f>& pts = *impl_->points;
  // The hint enters as a found point (with the tree's own distance arithmetic): the answer is still the least
  // (distance, index), whatever was found first.
  if (hint < pts.size() && is_finite(pts[hint])) {
    const float d = dist_sq(pts[hint], query.data());
    if (d <= max_sq) set.seed(hint, d);
  }
  set.bound(max_sq);
  impl_->find(set, query);
  return best;
}

float search_bound_mm(double max_distance_mm) {
  return static_cast<float>(max_distance_mm * (1.0 + 1e-4) + 1e-6);
}

float KdTree::distance_sq(std::uint32_t index, const Eigen::Vector3f& query) const {
  return dist_sq((*impl_->points)[index], query.data());
}

void KdTree::radius(const Eigen::Vector3f& query, float radius_mm, std::vector<Neighbor>& out) const {
  radius_unsorted(query, radius_mm, out);
  std::sort(out.begin(), out.end(), [](const Neighbor& a, const Neighbor& b) {
    return a.distance_sq < b.distance_sq || (a.distance_sq == b.distance_sq && a.index < b.index);
  });
}

void KdTree::radius_unsorted(const Eigen::Vector3f& query, float radius_mm, std::vector<Neighbor>& out) const {
  out.clear();
  if (!impl_ || impl_->count == 0 || !(radius_mm >= 0) || !is_finite(query)) return;
  RadiusSet set(radius_mm * radius_mm, out, impl_->id_map());
  impl_->find(set, query);
}

std::size_t KdTree::count_within(const Eigen::Vector3f& query, float radius_mm, std::size_t stop_at) const {
  if (!impl_ || impl_->count == 0 || stop_at == 0 || !(radius_mm >= 0) || !is_finite(query)) return 0;
  CountSet set(radius_mm * radius_mm, stop_at);
  impl_->find(set, query);
  return set.size();
}

}  // namespace ewis
