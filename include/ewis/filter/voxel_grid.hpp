#pragma once
// Voxel-grid down-sampling: one point per occupied voxel (the centroid of its points).
// Voxels are aligned to the minimum corner of the cloud's bounds; non-finite points are ignored.
#include <cstdint>
#include <vector>

#include "ewis/core/cloud.hpp"

namespace ewis {

struct VoxelGridResult {
  Cloud cloud;                                 // centroids (normals averaged and renormalised when present;
                                               // colours, intensities and scalar fields averaged)
  std::vector<std::uint32_t> representative;   // per output point, the input point nearest its centroid
};

// Deterministic: output ordered by voxel key (z-major: x fastest). Throws InputError when voxel_mm <= 0
// or the grid would overflow 64-bit keys.
VoxelGridResult voxel_downsample(const Cloud& cloud, double voxel_mm);

}  // namespace ewis
