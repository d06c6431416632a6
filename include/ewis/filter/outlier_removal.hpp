#pragma once
// Radius outlier removal (paper 4.1.1): a point with fewer than k OTHER points within r is removed.
//
// Parameters left at their "derive" values come from the resolution R = the MEDIAN nearest-neighbour
// distance (spatial_resolution().median_mm; the mean when the median is 0). The median, not the paper's
// mean R(PC): with ~40% outliers the mean is inflated by the isolated points, the median stays at the
// surface spacing s as long as most points lie on surfaces.
//   r = radius_factor x R                      (default 4 x s)
//   k = max(min_neighbors_floor, round(neighbor_fraction x pi x (r / R)^2))
// Why: a point inside a surface sampled at spacing s has about pi r^2 / s^2 neighbours within r (~50 for
// r = 4 s); on a boundary about half, at a corner a quarter, on a thin cable's visible strip fewer still.
// Requiring 10% of the interior count keeps all of those with a margin of 2 or more, while the floor of 6
// removes any cluster of up to 6 "flying pixels" (each of its points sees at most 5 others) and isolated
// outliers (a uniform outlier rarely has even one point within 4 s).
#include <cstdint>
#include <vector>

#include "ewis/core/cloud.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis {

struct RadiusOutlierParams {
  double radius_mm = 0.0;   // <= 0: derived from the resolution (radius_factor x R)
  int min_neighbors = -1;   // < 0: derived from the resolution (0 keeps every point)
  double radius_factor = 4.0;
  double neighbor_fraction = 0.1;   // k as a fraction of the neighbours of an interior surface point
  int min_neighbors_floor = 6;      // derived k is at least this (removes clusters of <= 6 points)
  std::size_t resolution_samples = 200000;  // points sampled (evenly strided) to measure R; 0: all
};

struct RadiusOutlierResult {
  std::vector<std::uint32_t> kept;  // indices of kept points, increasing
  double radius_mm = 0.0;           // the parameters used
  int min_neighbors = 0;
  double resolution_mm = 0.0;       // R measured (median NN distance; 0 when both parameters were given)
};

// One pass of count-limited radius queries on `tree` (each stops at k + 1 points), in parallel;
// deterministic. Non-finite points are removed (unless k = 0).
RadiusOutlierResult remove_radius_outliers(const KdTree& tree, const RadiusOutlierParams& params);

}  // namespace ewis
