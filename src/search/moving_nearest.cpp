// MovingNearest: per moving point, the k nearest target points around where it last was (see the header).
#include "ewis/search/moving_nearest.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ewis {
namespace {

// Float rounding of the distances: coordinates of ~1 m carry ~1e-4 mm.
constexpr float kSafetyMm = 1e-3f;

}  // namespace

MovingNearest::MovingNearest(const KdTree& tree, std::vector<std::uint32_t> ids)
    : tree_(tree), ids_(std::move(ids)), entries_(ids_.size()) {}

void MovingNearest::serve(std::vector<std::uint32_t> ids) {
  if (ids == ids_) return;
  std::vector<Entry> entries(ids.size());
  for (std::size_t k = 0, old = 0; k < ids.size(); ++k) {  // both increasing: one walk
    while (old < ids_.size() && ids_[old] < ids[k]) ++old;
    if (old < ids_.size() && ids_[old] == ids[k]) entries[k] = entries_[old];
  }
  ids_ = std::move(ids);
  entries_ = std::move(entries);
}

Neighbor MovingNearest::nearest(std::uint32_t id, const Eigen::Vector3f& query, float max_distance_mm,
                                std::uint32_t hint) {
  constexpr Neighbor kNone{std::numeric_limits<std::uint32_t>::max(), std::numeric_limits<float>::infinity()};
  const auto slot = std::lower_bound(ids_.begin(), ids_.end(), id);
  if (slot == ids_.end() || *slot != id) return tree_.nearest(query, max_distance_mm, hint);
  Entry& e = entries_[std::size_t(slot - ids_.begin())];
  if (e.radius > 0 && query.allFinite()) {
    const float sure = e.radius - (query - e.at).norm() - kSafetyMm;  // nothing outside the list is this near
    if (sure > 0) {
      Neighbor best = kNone;
      for (std::uint32_t k = 0; k < e.count; ++k) {
        const float d = tree_.distance_sq(e.ids[k], query);
        if (d < best.distance_sq || (d == best.distance_sq && e.ids[k] < best.index)) best = {e.ids[k], d};
      }
      const float max_sq = max_distance_mm * max_distance_mm;
      if (best.distance_sq <= sure * sure) return best.distance_sq <= max_sq ? best : kNone;
      if (sure >= max_distance_mm) return kNone;  // the list's best lies beyond `sure`, and so does the rest
    }
  }
  const Neighbor nb = tree_.nearest(query, max_distance_mm, hint);
  e.at = query;
  e.count = 0;
  e.radius = 0;
  if (!query.allFinite()) return nb;
  if (nb.index == kNone.index) {
    e.radius = max_distance_mm;  // nothing within it: every target point lies farther
    return nb;
  }
  std::vector<Neighbor> list;
  tree_.knn(query, static_cast<int>(kList), list);
  e.count = static_cast<std::uint32_t>(list.size());
  for (std::uint32_t k = 0; k < e.count; ++k) e.ids[k] = list[k].index;
  // Fewer than kList: the whole target is in the list.
  e.radius = e.count < kList ? std::numeric_limits<float>::infinity() : std::sqrt(list.back().distance_sq);
  return nb;
}

}  // namespace ewis
