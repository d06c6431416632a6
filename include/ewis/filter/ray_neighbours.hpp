#pragma once
// What a sensor saw on the rays next to a point's own: the points within lateral_mm of the point's ray (the line from
// the viewpoint through it) and within reach_mm of it along that ray, split by where they lie along it: at its range
// (within tolerance_mm), in front of it (nearer the sensor) or behind it. A point of a seen surface has neighbours at
// its range there (the surface goes on); a wrong range (a sensor's mismatch, another simulator's outlier moved a few
// mm) floats in front of the surface it came from, or beside it, with none (InterferenceParams::float_*,
// ScanToCadParams::box_surface_min_same).
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "ewis/search/kdtree.hpp"

namespace ewis {

struct RayNeighbourParams {
  double lateral_mm = 0.75;   // about 1.5 x the scan's resolution: the rays of the 8 pixels around it
  double tolerance_mm = 0.6;  // "at its range"
  double reach_mm = 5.0;      // along the ray, either way
};

struct RayNeighbours {
  std::size_t same = 0;    // within tolerance_mm of its range
  std::size_t front = 0;   // nearer the viewpoint
  std::size_t behind = 0;  // farther
};

// Over the tree's points; `self` (an index into them, or ~0u) is not counted. `scratch` is reused.
RayNeighbours ray_neighbours(const KdTree& tree, std::uint32_t self, const Eigen::Vector3d& p,
                             const Eigen::Vector3d& viewpoint, const RayNeighbourParams& params,
                             std::vector<Neighbor>& scratch);

}  // namespace ewis
