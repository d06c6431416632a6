// Outliers of a structured-light scan (paper 4.1.2, Fig. 7: ~40% of the points are noise): isolated points
// in the frustum near the scene's depth range, small clusters of 2-4 adjacent "flying pixels" at wrong
// depths, and mixed pixels at depth discontinuities (a depth between the foreground and the background).
#include <algorithm>
#include <cmath>

#include "ewis/core/parallel.hpp"
#include "ewis/sim/sensor.hpp"
#include "rng.hpp"

namespace ewis::sim {

void add_outliers(const Camera& camera, const std::vector<float>& depth, const SensorParams& params,
                  ScanResult& out) {
  const int w = camera.width_px, h = camera.height_px;
  const std::size_t n_valid = out.surface_points;
  if (n_valid == 0) return;
  const double f = std::clamp(params.outlier_fraction, 0.0, 0.95);
  const std::size_t n_out = static_cast<std::size_t>(std::llround(n_valid * f / (1.0 - f)));
  float dmin = std::numeric_limits<float>::infinity(), dmax = 0;
  for (std::size_t k = 0; k < n_valid; ++k) {
    const float d = depth[out.pixel[k]];
    dmin = std::min(dmin, d);
    dmax = std::max(dmax, d);
  }
  const double total_share = std::max(1e-9, params.isolated_share + params.flying_share + params.mixed_share);
  std::size_t n_mixed = static_cast<std::size_t>(std::llround(n_out * params.mixed_share / total_share));
  std::size_t n_flying = static_cast<std::size_t>(std::llround(n_out * params.flying_share / total_share));
  n_mixed = std::min(n_mixed, n_out);
  n_flying = std::min(n_flying, n_out - n_mixed);

  // Depth edges: a pixel and its right or lower neighbour, both measured, far apart in depth.
  const std::size_t n = static_cast<std::size_t>(w) * h;
  const auto jump = [&](std::size_t i, std::size_t j) {
    const float a = depth[i], b = depth[j];
    return std::isfinite(a) && std::isfinite(b) && std::abs(a - b) > std::max(5.0f, 0.02f * std::min(a, b));
  };
  const std::vector<std::uint32_t> edges = parallel_select(n, [&](std::size_t i) {
    const std::size_t c = i % w, r = i / w;
    return (c + 1 < std::size_t(w) && jump(i, i + 1)) || (r + 1 < std::size_t(h) && jump(i, i + w));
  });
  if (edges.empty()) n_mixed = 0;
  const std::size_t n_isolated = n_out - n_mixed - n_flying;

  const std::size_t base = out.cloud.size();
  out.cloud.points.resize(base + n_out);
  out.kind.resize(base + n_out, PointKind::Isolated);
  out.element.resize(base + n_out, kNoElement);
  out.pixel.resize(base + n_out, 0);
  const auto put = [&](std::size_t k, double u, double v, double d, PointKind kind) {
    const Eigen::Vector3d dir = camera.ray(u, v).normalized();
    out.cloud.points[k] = (dir * d).cast<float>();
    out.kind[k] = kind;
    out.pixel[k] = static_cast<std::uint32_t>(std::clamp(int(v), 0, h - 1) * w + std::clamp(int(u), 0, w - 1));
  };

  // Mixed pixels: on an edge pixel's own ray, between its depth and its neighbour's.
  parallel_for_each_index(n_mixed, [&](std::size_t k) {
    Rng rng(mix(params.seed, k, 2));
    const std::size_t i = edges[rng.next() % edges.size()];
    const std::size_t c = i % w, r = i / w;
    std::size_t j = i + 1;
    if (!(c + 1 < std::size_t(w) && jump(i, j))) j = i + w;
    const std::size_t p = rng.chance(0.5) ? i : j;
    const double d = depth[i] + rng.uniform(0.15, 0.85) * (depth[j] - depth[i]);
    put(base + k, (p % w) + 0.5, (p / w) + 0.5, d, PointKind::Mixed);
    (void)r;
  });

  // Flying pixels: clusters of 2-4 neighbouring pixels, all at about the same wrong depth.
  std::size_t k = 0;
  for (std::uint64_t cluster = 0; k < n_flying && cluster < 4 * n_flying + 16; ++cluster) {
    Rng rng(mix(params.seed, cluster, 3));
    const std::size_t anchor = out.pixel[rng.next() % n_valid];
    const int size = std::min<int>(rng.integer(2, 4), static_cast<int>(n_flying - k));
    const double d0 = depth[anchor] + (rng.chance(0.5) ? 1.0 : -1.0) * rng.uniform(15.0, 120.0);
    const bool horizontal = rng.chance(0.5);
    const int c0 = static_cast<int>(anchor % w), r0 = static_cast<int>(anchor / w);
    for (int m = 0; m < size; ++m) {
      const int c = std::min(w - 1, c0 + (horizontal ? m : 0)), r = std::min(h - 1, r0 + (horizontal ? 0 : m));
      put(base + n_mixed + k, c + 0.5, r + 0.5, std::max(1.0, d0 + rng.uniform(-1.5, 1.5)), PointKind::Flying);
      ++k;
    }
  }
  n_flying = k;

  // Isolated points anywhere in the frustum, within 100 mm of the scene's depth range.
  const double lo = std::max(params.min_range_mm, double(dmin) - 100.0), hi = double(dmax) + 100.0;
  parallel_for_each_index(n_isolated, [&](std::size_t q) {
    Rng rng(mix(params.seed, q, 4));
    const double u = rng.uniform(0.0, w), v = rng.uniform(0.0, h);
    put(base + n_mixed + n_flying + q, u, v, rng.uniform(lo, hi), PointKind::Isolated);
  });
  const std::size_t total = base + n_mixed + n_flying + n_isolated;
  out.cloud.points.resize(total);
  out.kind.resize(total);
  out.element.resize(total);
  out.pixel.resize(total);
}

// See SensorParams::mismatch_patches. `valid` lists the measured pixels in increasing order (point k is valid[k]);
// `depth` is each pixel's measured range, updated. Patches are drawn one after another from their own seeds.
void add_mismatch_patches(const Camera& camera, const std::vector<std::uint32_t>& valid, std::vector<float>& depth,
                          const SensorParams& params, ScanResult& out) {
  const int w = camera.width_px, h = camera.height_px;
  if (valid.empty()) return;
  const int lo = std::max(1, std::min(params.mismatch_min_px, params.mismatch_max_px));
  const int hi = std::max(lo, params.mismatch_max_px);
  for (int patch = 0; patch < params.mismatch_patches; ++patch) {
    Rng rng(mix(params.seed, static_cast<std::uint64_t>(patch), 5));
    const std::uint32_t anchor = valid[rng.next() % valid.size()];
    const int side = rng.integer(lo, hi);
    const double offset_mm =
        (rng.chance(0.5) ? 1.0 : -1.0) * rng.uniform(params.mismatch_min_mm, params.mismatch_max_mm);
    const float d0 = depth[anchor];
    const int c0 = static_cast<int>(anchor % w) - side / 2, r0 = static_cast<int>(anchor / w) - side / 2;
    for (int r = std::max(0, r0); r < std::min(h, r0 + side); ++r)
      for (int c = std::max(0, c0); c < std::min(w, c0 + side); ++c) {
        const std::uint32_t p = static_cast<std::uint32_t>(r * w + c);
        const auto it = std::lower_bound(valid.begin(), valid.end(), p);
        if (it == valid.end() || *it != p) continue;
        const std::size_t k = static_cast<std::size_t>(it - valid.begin());
        if (out.kind[k] != PointKind::Surface || std::abs(depth[p] - d0) > 5.0f) continue;  // one surface a patch
        const Eigen::Vector3d x = out.cloud.points[k].cast<double>();
        const double range = x.norm();
        if (!(range + offset_mm > 1.0)) continue;
        out.cloud.points[k] = (x * ((range + offset_mm) / range)).cast<float>();
        depth[p] = static_cast<float>(range + offset_mm);
        out.kind[k] = PointKind::Mismatch;
        ++out.mismatched;
      }
  }
}

}  // namespace ewis::sim
