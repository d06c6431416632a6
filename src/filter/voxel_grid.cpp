// Voxel-grid down-sampling (the re-sampling of paper 4.1.1 before registration): one point per occupied voxel.
// Points get integer voxel keys, a stable parallel LSD radix sort groups them by key (ties keep index order, so
// the output is one and the same for any thread count), and each run of equal keys becomes one output point.
#include "ewis/filter/voxel_grid.hpp"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "ewis/core/error.hpp"
#include "ewis/core/parallel.hpp"
#include "ewis/core/scratch.hpp"

namespace ewis {
namespace {

bool is_finite(const Eigen::Vector3f& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()); }

struct Bounds {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::infinity());
  Eigen::Vector3f hi = Eigen::Vector3f::Constant(-std::numeric_limits<float>::infinity());
};

// Exact min/max of the finite points (min and max do not round, so the block split cannot change them).
Bounds finite_bounds(const std::vector<Eigen::Vector3f>& pts) {
  return parallel_reduce_ordered(
      pts.size(), 1 << 16, Bounds{},
      [&](std::size_t b, std::size_t e) {
        Bounds r;
        for (std::size_t i = b; i < e; ++i)
          if (is_finite(pts[i])) r.lo = r.lo.cwiseMin(pts[i]), r.hi = r.hi.cwiseMax(pts[i]);
        return r;
      },
      [](const Bounds& a, const Bounds& b) { return Bounds{a.lo.cwiseMin(b.lo), a.hi.cwiseMax(b.hi)}; });
}

// Stable LSD radix sort of `v` on bits [lo_bit, lo_bit + bits), in passes of at most 11 bits. Each pass counts
// digits per fixed block, turns the counts into block-ordered offsets and scatters the blocks in parallel; a
// stable sort has one result, so neither the blocks nor the thread count can change it. `tmp` is scratch.
void radix_sort(ScratchArray<std::uint64_t>& v, int lo_bit, int bits) {
  const std::size_t n = v.size();
  if (n < 2 || bits <= 0) return;
  const int passes = (bits + 10) / 11;
  const int width = (bits + passes - 1) / passes;
  const std::size_t radix = std::size_t{1} << width;
  const std::size_t grain = std::max<std::size_t>(std::size_t{1} << 16, (n + 63) / 64);
  const std::size_t blocks = (n + grain - 1) / grain;
  std::vector<std::uint32_t> offsets(blocks * radix);
  ScratchArray<std::uint64_t> tmp(n);
  for (int p = 0; p < passes; ++p) {
    const int shift = lo_bit + p * width;
    const std::uint64_t mask = radix - 1;
    parallel_blocks(n, grain, [&](std::size_t b, std::size_t e) {
      std::uint32_t* count = offsets.data() + (b / grain) * radix;
      std::fill(count, count + radix, 0u);
      for (std::size_t i = b; i < e; ++i) ++count[(v[i] >> shift) & mask];
    });
    std::uint32_t sum = 0;  // digit-major, block-minor: the stable order
    for (std::size_t d = 0; d < radix; ++d)
      for (std::size_t k = 0; k < blocks; ++k) {
        const std::uint32_t c = offsets[k * radix + d];
        offsets[k * radix + d] = sum;
        sum += c;
      }
    parallel_blocks(n, grain, [&](std::size_t b, std::size_t e) {
      std::uint32_t* at = offsets.data() + (b / grain) * radix;
      for (std::size_t i = b; i < e; ++i) tmp[at[(v[i] >> shift) & mask]++] = v[i];
    });
    v.swap(tmp);
  }
}

// One output point per run [starts[v], starts[v+1]) of the sorted order; index_at(j) is the input index at sorted
// position j (ascending within a run). Sums run in index order, so every value is independent of the threads.
template <class IndexAt>
void average_runs(const Cloud& cloud, const ScratchArray<std::uint32_t>& starts, const IndexAt& index_at,
                  VoxelGridResult& result) {
  const std::size_t n = cloud.size(), m = starts.size() - 1;
  Cloud& out = result.cloud;
  out.points.resize(m);
  result.representative.resize(m);
  if (cloud.has_normals()) out.normals.resize(m);
  if (cloud.has_colors()) out.colors.resize(m);
  if (cloud.has_intensities()) out.intensities.resize(m);
  for (const auto& f : cloud.scalars) out.scalars.push_back({f.name, std::vector<float>(m)});

  parallel_for_each_index(m, [&](std::size_t v) {
    const std::size_t b = starts[v], e = starts[v + 1];
    const double cnt = static_cast<double>(e - b);
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (std::size_t j = b; j < e; ++j) c += cloud.points[index_at(j)].template cast<double>();
    c /= cnt;
    out.points[v] = c.cast<float>();
    // representative: the input point nearest the centroid, ties to the smallest index (runs are sorted)
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t j = b; j < e; ++j) {
      const double d = (cloud.points[index_at(j)].template cast<double>() - c).squaredNorm();
      if (d < best) {
        best = d;
        result.representative[v] = index_at(j);
      }
    }
    if (cloud.has_normals()) {
      Eigen::Vector3d s = Eigen::Vector3d::Zero();
      for (std::size_t j = b; j < e; ++j) s += cloud.normals[index_at(j)].template cast<double>();
      // opposite normals cancel: fall back to the representative's
      out.normals[v] = s.norm() > 1e-12 ? s.normalized().cast<float>() : cloud.normals[result.representative[v]];
    }
    if (cloud.has_colors()) {
      double rgb[3] = {0, 0, 0};
      for (std::size_t j = b; j < e; ++j)
        for (int a = 0; a < 3; ++a) rgb[a] += cloud.colors[index_at(j)][a];
      for (int a = 0; a < 3; ++a) out.colors[v][a] = static_cast<std::uint8_t>(std::lround(rgb[a] / cnt));
    }
    if (cloud.has_intensities()) {
      double s = 0;
      for (std::size_t j = b; j < e; ++j) s += cloud.intensities[index_at(j)];
      out.intensities[v] = static_cast<float>(s / cnt);
    }
    for (std::size_t f = 0; f < cloud.scalars.size(); ++f) {
      const auto& vals = cloud.scalars[f].values;
      if (vals.size() != n) continue;
      double s = 0;
      for (std::size_t j = b; j < e; ++j) s += vals[index_at(j)];
      out.scalars[f].values[v] = static_cast<float>(s / cnt);
    }
  }, 4096);
}

// First sorted positions of each run of equal keys among [0, end), plus `end`: counted per fixed block, then
// written at the block's offset (two reads of the keys, no per-block vectors).
template <class KeyAt>
ScratchArray<std::uint32_t> run_starts(std::size_t end, const KeyAt& key_at) {
  const std::size_t grain = 1 << 16, blocks = (end + grain - 1) / grain;
  std::vector<std::uint32_t> first(blocks + 1, 0);
  const auto is_start = [&](std::size_t j) { return j == 0 || key_at(j) != key_at(j - 1); };
  parallel_blocks(end, grain, [&](std::size_t b, std::size_t e) {
    std::uint32_t c = 0;
    for (std::size_t j = b; j < e; ++j) c += is_start(j);
    first[b / grain + 1] = c;
  });
  for (std::size_t k = 0; k < blocks; ++k) first[k + 1] += first[k];
  ScratchArray<std::uint32_t> starts(first[blocks] + 1);
  parallel_blocks(end, grain, [&](std::size_t b, std::size_t e) {
    std::uint32_t at = first[b / grain];
    for (std::size_t j = b; j < e; ++j)
      if (is_start(j)) starts[at++] = static_cast<std::uint32_t>(j);
  });
  starts[starts.size() - 1] = static_cast<std::uint32_t>(end);
  return starts;
}

}  // namespace

VoxelGridResult voxel_downsample(const Cloud& cloud, double voxel_mm) {
  if (!(voxel_mm > 0) || !std::isfinite(voxel_mm))
    throw InputError("", "voxel size must be a positive number of mm, got " + std::to_string(voxel_mm));
  VoxelGridResult result;
  const std::size_t n = cloud.size();
  const Bounds bounds = finite_bounds(cloud.points);
  if (!(bounds.lo.x() <= bounds.hi.x())) return result;  // empty, or no finite point
  const Eigen::Vector3d lo = bounds.lo.cast<double>(), hi = bounds.hi.cast<double>();

  // Voxel counts per axis; keys are z-major linear indices (x fastest), so they must fit in 63 bits.
  std::uint64_t dims[3];
  double cells = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double d = std::floor((hi[a] - lo[a]) / voxel_mm) + 1.0;
    cells *= d;
    if (!std::isfinite(d) || cells >= 9.0e18)
      throw InputError("", "voxel size " + std::to_string(voxel_mm) + " mm is too small for the cloud's extent");
    dims[a] = static_cast<std::uint64_t>(d);
  }
  // Voxel index per axis: floor((p - lo) / voxel_mm), clamped into the grid. p >= lo, so the quotient is >= 0 and
  // truncation is the floor (std::floor is a libm call on baseline x86-64, and this loop runs per point).
  const double top[3] = {double(dims[0] - 1), double(dims[1] - 1), double(dims[2] - 1)};
  auto key_of = [&](const Eigen::Vector3f& p) {
    std::uint64_t idx[3];
    for (int a = 0; a < 3; ++a) {
      const double q = (double(p[a]) - lo[a]) / voxel_mm;
      idx[a] = static_cast<std::uint64_t>(static_cast<std::int64_t>(std::min(std::max(q, 0.0), top[a])));
    }
    return idx[0] + dims[0] * (idx[1] + dims[1] * idx[2]);
  };
  // Non-finite points get the key one past the last voxel: they sort last and are dropped.
  const std::uint64_t non_finite = dims[0] * dims[1] * dims[2];
  const int key_bits = std::bit_width(non_finite);
  const int index_bits = std::max(1, static_cast<int>(std::bit_width(n)));

  if (key_bits + index_bits <= 64) {
    // One 64-bit word per point, key above index: sorting on the key bits alone keeps the indices ascending
    // within a voxel (stable sort of an index-ordered array), and the sorted words carry the indices.
    ScratchArray<std::uint64_t> packed(n);
    parallel_blocks(n, 1 << 14, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        const auto& p = cloud.points[i];
        packed[i] = ((is_finite(p) ? key_of(p) : non_finite) << index_bits) | i;
      }
    });
    radix_sort(packed, index_bits, key_bits);
    std::size_t finite_end = n;
    while (finite_end > 0 && (packed[finite_end - 1] >> index_bits) == non_finite) --finite_end;
    const ScratchArray<std::uint32_t> starts =
        run_starts(finite_end, [&](std::size_t j) { return packed[j] >> index_bits; });
    const std::uint64_t index_mask = (std::uint64_t{1} << index_bits) - 1;
    average_runs(cloud, starts, [&](std::size_t j) { return static_cast<std::uint32_t>(packed[j] & index_mask); },
                 result);
  } else {
    // Keys too wide to pack with the index (an enormous grid): sort (key, index) pairs, which are unique, so an
    // unstable parallel sort still has one result.
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(n);
    parallel_for_each_index(n, [&](std::size_t i) {
      keyed[i] = {is_finite(cloud.points[i]) ? key_of(cloud.points[i]) : non_finite, static_cast<std::uint32_t>(i)};
    });
    tbb::parallel_sort(keyed.begin(), keyed.end());
    std::size_t finite_end = n;
    while (finite_end > 0 && keyed[finite_end - 1].first == non_finite) --finite_end;
    const ScratchArray<std::uint32_t> starts = run_starts(finite_end, [&](std::size_t j) { return keyed[j].first; });
    average_runs(cloud, starts, [&](std::size_t j) { return keyed[j].second; }, result);
  }
  return result;
}

}  // namespace ewis
