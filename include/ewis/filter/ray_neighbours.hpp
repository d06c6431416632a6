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

// The surface seen on the rays around a point's own: of the points within lateral_mm of its ray and reach_mm of it
// along the ray, those on the `rays` rays nearest to its own (the pixels around it; points within same_ray_mm of one
// another across the rays are one ray's, a stack; those on the point's own ray are left out), and the plane over them
// that the most rays hold within tolerance_mm along the rays (through a point of each of three rays, every such
// triple tried; then refitted to the holding point of each ray). A point lies on the surface its neighbours saw when
// that plane, held by at least min_inliers rays, passes within tolerance_mm of it along its ray. Unlike a count of
// neighbours at its range, this keeps a surface seen at a grazing angle or sparsely (pixels lost), whose neighbours lie
// in front of it on one side and behind it on the other; a range moved off its surface has the plane of that surface
// in front of or behind it.
struct RaySurfaceParams {
  double lateral_mm = 1.25;   // about 2.5 x the scan's resolution: enough rays around it under lost pixels
  double same_ray_mm = 0.125;  // about a quarter of the resolution
  double tolerance_mm = 0.6;
  double reach_mm = 5.0;
  std::size_t rays = 8;
  std::size_t min_inliers = 4;  // a plane through 3 always fits
};

struct RaySurface {
  std::size_t neighbours = 0;  // rays used (at most `rays`)
  std::size_t inliers = 0;     // rays holding the best plane
  double offset_mm = 0.0;      // where the plane crosses the point's ray, from the point (+: behind it)
  bool on = false;             // inliers >= min_inliers and |offset_mm| <= tolerance_mm
};

RaySurface seen_surface_at(const KdTree& tree, std::uint32_t self, const Eigen::Vector3d& p,
                           const Eigen::Vector3d& viewpoint, const RaySurfaceParams& params,
                           std::vector<Neighbor>& scratch);

}  // namespace ewis
