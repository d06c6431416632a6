#pragma once
// Area-weighted random sampling of CAD triangles (paper 4.1.1), per element, seeded.
#include <cstdint>
#include <vector>

#include "ewis/core/cloud.hpp"
#include "ewis/scene/scene.hpp"

namespace ewis {

struct MeshSamplingParams {
  double spacing_mm = 1.0;              // target mean spacing: count = area / spacing^2
  std::size_t max_points = 0;           // 0: no cap; else at most this many per call
  std::uint64_t seed = 1;
  std::vector<int> elements;            // element indices to sample; empty: all
};

struct MeshSamples {
  Cloud cloud;                          // points with the triangle normals
  std::vector<std::uint32_t> element;   // element index of each point
  std::vector<std::uint32_t> triangle;  // triangle index of each point
};

// Deterministic for a seed, independent of the thread count.
MeshSamples sample_mesh(const Scene& scene, const MeshSamplingParams& params);

}  // namespace ewis
