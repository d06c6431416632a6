// Near-uniform mesh samples: area-weighted candidates thinned by weighted sample elimination
// (C. Yuksel, "Sample Elimination for Generating Poisson Disk Sample Sets", 2015). paper 4.1.1: the CAD
// points and the scan should have the same resolution ("data re-sampling"); even spacing makes that hold.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <queue>

#include "ewis/core/parallel.hpp"
#include "ewis/sample/mesh_sampling.hpp"

namespace ewis {
namespace {

struct Range {
  std::uint32_t element = 0;
  std::size_t begin = 0, end = 0;  // candidates of this element
  std::size_t target = 0;          // samples to keep
};

// Indices (into [begin, end)) of the `target` candidates that survive elimination, in increasing order.
std::vector<std::size_t> eliminate(const std::vector<Eigen::Vector3f>& pts, const Range& r, double area) {
  const std::size_t m = r.end - r.begin;
  std::vector<std::size_t> keep;
  if (r.target >= m) {
    for (std::size_t i = r.begin; i < r.end; ++i) keep.push_back(i);
    return keep;
  }
  // Yuksel's r_max for a 2D domain: the spacing of a hexagonal packing of `target` points.
  const double rmax = std::sqrt(area / (2.0 * std::sqrt(3.0) * double(r.target)));
  const double reach = 2.0 * rmax;
  // Sort candidates into a grid of cells of size `reach`; neighbours are in the 27 surrounding cells.
  auto cell_of = [&](const Eigen::Vector3f& p) {
    return Eigen::Vector3i(int(std::floor(p.x() / reach)), int(std::floor(p.y() / reach)), int(std::floor(p.z() / reach)));
  };
  auto key = [](const Eigen::Vector3i& c) {
    return (std::uint64_t(std::uint32_t(c.x()) & 0x1FFFFF) << 42) | (std::uint64_t(std::uint32_t(c.y()) & 0x1FFFFF) << 21) |
           std::uint64_t(std::uint32_t(c.z()) & 0x1FFFFF);
  };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> sorted(m);
  for (std::size_t i = 0; i < m; ++i) sorted[i] = {key(cell_of(pts[r.begin + i])), std::uint32_t(i)};
  std::sort(sorted.begin(), sorted.end());
  // Neighbour lists with weights w(d) = (1 - d / 2 r_max)^8 (the paper's alpha = 8).
  std::vector<std::vector<std::pair<std::uint32_t, float>>> nbr(m);
  std::vector<double> weight(m, 0.0);
  for (std::size_t i = 0; i < m; ++i) {
    const Eigen::Vector3f& p = pts[r.begin + i];
    const Eigen::Vector3i c = cell_of(p);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const std::uint64_t k = key(c + Eigen::Vector3i(dx, dy, dz));
          auto it = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(k, std::uint32_t(0)));
          for (; it != sorted.end() && it->first == k; ++it) {
            const std::uint32_t j = it->second;
            if (j == i) continue;
            const double d = (pts[r.begin + j] - p).cast<double>().norm();
            if (d >= reach) continue;
            const float w = float(std::pow(1.0 - d / reach, 8.0));
            nbr[i].emplace_back(j, w);
            weight[i] += w;
          }
        }
    std::sort(nbr[i].begin(), nbr[i].end());  // fixed order: the weight updates below are reproducible
  }
  // Remove the heaviest candidate (the most crowded) until `target` remain; lazy max-heap.
  std::priority_queue<std::pair<double, std::uint32_t>> heap;
  for (std::size_t i = 0; i < m; ++i) heap.emplace(weight[i], std::uint32_t(i));
  std::vector<char> removed(m, 0);
  std::size_t remaining = m;
  while (remaining > r.target && !heap.empty()) {
    const auto [w, i] = heap.top();
    heap.pop();
    if (removed[i] || w != weight[i]) continue;  // stale entry
    removed[i] = 1;
    --remaining;
    for (const auto& [j, wj] : nbr[i]) {
      if (removed[j]) continue;
      weight[j] -= wj;
      heap.emplace(weight[j], j);
    }
  }
  for (std::size_t i = 0; i < m; ++i)
    if (!removed[i]) keep.push_back(r.begin + i);
  return keep;
}

}  // namespace

MeshSamples sample_mesh_uniform(const Scene& scene, const MeshSamplingParams& params, double oversample) {
  oversample = std::clamp(oversample, 1.0, 64.0);
  MeshSamplingParams dense = params;
  dense.spacing_mm = params.spacing_mm / std::sqrt(oversample);
  if (params.max_points > 0) dense.max_points = static_cast<std::size_t>(double(params.max_points) * oversample);
  const MeshSamples cand = sample_mesh(scene, dense);  // validates the parameters

  // Candidates come grouped by element, in the order of params.elements.
  std::vector<Range> ranges;
  for (std::size_t i = 0; i < cand.element.size(); ++i) {
    if (ranges.empty() || ranges.back().element != cand.element[i]) ranges.push_back({cand.element[i], i, i, 0});
    ranges.back().end = i + 1;
  }
  for (Range& r : ranges)
    r.target = std::max<std::size_t>(1, static_cast<std::size_t>(std::llround(double(r.end - r.begin) / oversample)));

  std::vector<std::vector<std::size_t>> kept(ranges.size());
  parallel_for_each_index(ranges.size(), [&](std::size_t k) {
    kept[k] = eliminate(cand.cloud.points, ranges[k], scene.elements[ranges[k].element].area_mm2);
  }, 1);

  std::vector<std::uint32_t> all;
  for (const auto& v : kept)
    for (std::size_t i : v) all.push_back(static_cast<std::uint32_t>(i));
  MeshSamples out;
  out.cloud = select(cand.cloud, all);
  out.element.reserve(all.size());
  out.triangle.reserve(all.size());
  for (std::uint32_t i : all) {
    out.element.push_back(cand.element[i]);
    out.triangle.push_back(cand.triangle[i]);
  }
  return out;
}

}  // namespace ewis
