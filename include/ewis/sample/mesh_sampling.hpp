#pragma once
// Area-weighted random sampling of CAD triangles (paper 4.1.1), per element, seeded.
#include <cstdint>
#include <functional>
#include <vector>

#include "ewis/core/cloud.hpp"
#include "ewis/scene/scene.hpp"

namespace ewis {

struct MeshSamplingParams {
  double spacing_mm = 1.0;              // target mean spacing: count = area / spacing^2
  std::size_t max_points = 0;           // 0: no cap; else at most this many per call
  std::uint64_t seed = 1;
  std::vector<int> elements;            // element indices to sample; empty: all
  // When set, only the samples it accepts are returned: the same samples, in the same order, as filtering the
  // full result afterwards, without ever holding the full result (a view of a large CAD). Thread-safe.
  using KeepFn = std::function<bool(const Eigen::Vector3f& point, const Eigen::Vector3f& normal)>;
  KeepFn keep;
};

struct MeshSamples {
  Cloud cloud;                          // points with the triangle normals
  std::vector<std::uint32_t> element;   // element index of each point
  std::vector<std::uint32_t> triangle;  // triangle index of each point
};

// Deterministic for a seed, independent of the thread count.
MeshSamples sample_mesh(const Scene& scene, const MeshSamplingParams& params);

// Near-uniform (blue-noise) variant: draws `oversample` times as many area-weighted candidates per element,
// then removes the candidates with the most close neighbours (weighted sample elimination, Yuksel 2015)
// until about area / spacing^2 remain per element. No clumps and no holes, so every part of the CAD gets
// the same weight in registration. Same fields, seed and thread-count independence as sample_mesh.
MeshSamples sample_mesh_uniform(const Scene& scene, const MeshSamplingParams& params, double oversample = 4.0);

}  // namespace ewis
