#pragma once
// Putting a cloud into k-d tree leaf order, so that trees built over it afterwards use its points in place.
#include "ewis/core/cloud.hpp"

namespace ewis {

// Permutes the cloud (positions and every attribute alike) into the leaf order of its k-d tree; non-finite
// points go to the end in their order. A KdTree built over the permuted points is the same tree but makes no
// copy of them (16 bytes a point less while it lives), and neighbours in space become neighbours in memory.
// Transient memory: 4 bytes a point (the order) and, up to `copy_max_points`, one attribute's copy at a time (12
// bytes a point for the positions; the copies are made in parallel); beyond that no copy of the cloud (permuted in
// place, slower).
void sort_for_search(Cloud& cloud, std::size_t copy_max_points = std::size_t(4) << 20);

}  // namespace ewis
