#pragma once
// Radius outlier removal (paper 4.1.1): a point with fewer than k other points within r is removed.
#include <cstdint>
#include <vector>

#include "ewis/core/cloud.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis {

struct RadiusOutlierParams {
  double radius_mm = 0.0;   // <= 0: derived from the resolution (radius_factor x R(PC))
  int min_neighbors = -1;   // < 0: derived from the resolution (0 keeps every point)
  double radius_factor = 4.0;
};

struct RadiusOutlierResult {
  std::vector<std::uint32_t> kept;  // indices of kept points, increasing
  double radius_mm = 0.0;           // the parameters used
  int min_neighbors = 0;
  double resolution_mm = 0.0;       // R(PC) measured (0 when both parameters were given)
};

RadiusOutlierResult remove_radius_outliers(const KdTree& tree, const RadiusOutlierParams& params);

}  // namespace ewis
