#pragma once
// Putting a cloud into k-d tree leaf order, so that trees built over it afterwards use its points in place.
#include "ewis/core/cloud.hpp"

namespace ewis {

// Permutes the cloud (positions and every attribute alike) into the leaf order of its k-d tree; non-finite
// points go to the end in their order. A KdTree built over the permuted points is the same tree but makes no
// copy of them (16 bytes a point less while it lives), and neighbours in space become neighbours in memory.
// Transient memory: 4 bytes a point (the order), no copy of the cloud.
void sort_for_search(Cloud& cloud);

}  // namespace ewis
