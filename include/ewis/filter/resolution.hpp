#pragma once
// Spatial resolution R(PC) (paper 4.1.1): the mean distance from each point to its nearest other point
// (a duplicate counts as 0), and the median, which outliers barely move (filters derive radii from it).
#include "ewis/core/cloud.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis {

struct ResolutionResult {
  double mean_mm = 0.0;     // R(PC); 0 for fewer than 2 points
  double median_mm = 0.0;
  std::size_t points = 0;   // points measured (finite ones of the sample)
};

// Deterministic for any thread count. `max_samples` > 0 estimates from an evenly strided subset.
ResolutionResult spatial_resolution(const KdTree& tree, std::size_t max_samples = 0);

}  // namespace ewis
