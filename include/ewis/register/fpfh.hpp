#pragma once
// Fast Point Feature Histograms (Rusu et al. 2009, as in PCL's FPFHEstimation): 3 x 11 bins of the Darboux
// frame angles (alpha, phi, theta) between a point and its neighbours (SPFH), then each point's SPFH plus the
// distance-weighted mean of its neighbours' SPFH. Each 11-bin part sums to 100.
#include <array>
#include <vector>

#include "ewis/search/kdtree.hpp"

namespace ewis {

using Fpfh = std::array<float, 33>;

struct FpfhParams {
  double radius_mm = 25.0;     // feature radius (typically 5 x the voxel size)
  std::size_t max_neighbors = 100;  // nearest ones within the radius (bounds the cost in dense spots)
};

// One feature per tree point; `normals` (unit, consistently oriented) parallel to tree.points().
// A point with no neighbour gets an all-zero feature. Deterministic for any thread count.
std::vector<Fpfh> compute_fpfh(const KdTree& tree, const std::vector<Eigen::Vector3f>& normals,
                               const FpfhParams& params = {});

}  // namespace ewis
