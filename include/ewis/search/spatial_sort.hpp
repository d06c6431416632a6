#pragma once
// Putting a cloud into k-d tree leaf order, so that trees built over it afterwards use its points in place.
#include "ewis/core/cloud.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis {

// Permutes the cloud (positions and every attribute alike) into the leaf order of its k-d tree, and returns that
// tree, which uses the permuted points in place (no copy of them: 16 bytes a point less while it lives; it refers to
// cloud.points, which must then stay where it is). Non-finite points go to the end in their order. Neighbours in
// space become neighbours in memory, and every tree built over the cloud afterwards is the same and copies nothing.
// Transient memory: up to `copy_max_points`, the positions' copy that the tree's build moves and the order (16
// bytes a point; the cloud's own positions are freed before the build adds its nodes) and then one other
// attribute's copy at a time (gathered in parallel); beyond that 4 bytes a point for the order and no copy of the
// cloud (permuted in place, one cycle at a time: about 2.6 times slower). The default, 16 Mi points (201 MB of
// positions), keeps the in-place way for the largest clouds only: on a 5.03 M-point scan it took the inspection's
// filter step from 2.37-2.63 to 1.09-1.34 s for 20 MB more at its peak (152 MB, 2.5x the positions; 4 Mi before).
KdTree sort_for_search(Cloud& cloud, std::size_t copy_max_points = std::size_t(16) << 20);

}  // namespace ewis
