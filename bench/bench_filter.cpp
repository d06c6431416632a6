// Filter-stage benchmarks on a realistic simulated scan: surfaces (plates, a bracket, cables, a dome) sampled at
// 0.5 mm with 0.1 mm noise, plus 40% outliers (uniform in the volume, and clusters of 2-4 flying pixels).
// Run: build/bin/bench_filter. Time = wall clock, CPU = the whole process (all threads); 2 cores here.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "ewis/filter/euclidean_clusters.hpp"
#include "ewis/filter/normals.hpp"
#include "ewis/filter/outlier_removal.hpp"
#include "ewis/filter/resolution.hpp"
#include "ewis/filter/voxel_grid.hpp"
#include "ewis/search/kdtree.hpp"
#include "ewis/search/spatial_sort.hpp"

using namespace ewis;

namespace {

constexpr float kSpacing = 0.5f;
constexpr float kNoise = 0.1f;

// ~0.78 M surface points and ~0.52 M outliers (40%), in a 400 x 300 x 170 mm volume.
std::vector<Eigen::Vector3f> make_scan() {
  std::mt19937 rng(2024);
  std::normal_distribution<float> noise(0.f, kNoise);
  std::uniform_real_distribution<float> jit(-0.1f, 0.1f);
  std::vector<Eigen::Vector3f> pts;
  auto add = [&](const Eigen::Vector3f& p, const Eigen::Vector3f& n) { pts.push_back(p + noise(rng) * n); };
  // floor plate 400 x 300 mm
  for (float y = 0; y < 300; y += kSpacing)
    for (float x = 0; x < 400; x += kSpacing) add({x + jit(rng), y + jit(rng), 0.f}, {0, 0, 1});
  // bracket tilted 45 deg, 200 x 150 mm
  const Eigen::Vector3f bn = Eigen::Vector3f(0, -1, 1).normalized();
  for (float v = 0; v < 150; v += kSpacing)
    for (float u = 0; u < 200; u += kSpacing)
      add(Eigen::Vector3f(100 + u, 200 + v * 0.7071f, 20 + v * 0.7071f), bn);
  // 12 cables of radius 2.5-4 mm, upper half visible, running along x at several heights
  for (int c = 0; c < 12; ++c) {
    const float r = 2.5f + 0.125f * c, y0 = 20.f + 14.f * c, z0 = 8.f + 3.f * (c % 4);
    const int around = int(M_PI * r / kSpacing);
    for (float x = 10; x < 310; x += kSpacing)
      for (int t = 0; t <= around; ++t) {
        const float th = float(M_PI) * t / around;
        const Eigen::Vector3f n(0, std::cos(th), std::sin(th));
        add(Eigen::Vector3f(x, y0, z0) + r * n, n);
      }
  }
  // dome (upper half sphere) radius 40 mm
  const int dome = int(2 * M_PI * 40 * 40 / (kSpacing * kSpacing));
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < dome; ++i) {
    const double z = 1.0 - (i + 0.5) / dome, rr = std::sqrt(1 - z * z), phi = golden * i;
    const Eigen::Vector3f n(float(rr * std::cos(phi)), float(rr * std::sin(phi)), float(z));
    add(Eigen::Vector3f(330, 80, 0) + 40.f * n, n);
  }
  // 40% outliers: 70% of them uniform in the volume, 30% in clusters of 2-4 within 0.5 mm
  const std::size_t surface = pts.size();
  const std::size_t outliers = surface * 2 / 3;
  std::uniform_real_distribution<float> ux(0, 400), uy(0, 300), uz(-20, 150), uc(-0.25f, 0.25f);
  std::uniform_int_distribution<int> csize(2, 4);
  std::size_t added = 0;
  while (added < outliers * 7 / 10) pts.emplace_back(ux(rng), uy(rng), uz(rng)), ++added;
  while (added < outliers) {
    const Eigen::Vector3f c(ux(rng), uy(rng), uz(rng));
    for (int k = csize(rng); k > 0 && added < outliers; --k, ++added) pts.push_back(c + Eigen::Vector3f(uc(rng), uc(rng), uc(rng)));
  }
  // scanners write points in scan order, not by surface: shuffle
  std::shuffle(pts.begin(), pts.end(), rng);
  return pts;
}

// The full scan (~1.3 M) or its part with x < 230 mm (~0.78 M, the size of DESIGN.md's comparison).
const std::vector<Eigen::Vector3f>& scan(bool small) {
  static const std::vector<Eigen::Vector3f> full = make_scan();
  static const std::vector<Eigen::Vector3f> part = [] {
    std::vector<Eigen::Vector3f> p;
    for (const auto& q : full)
      if (q.x() < 230.f) p.push_back(q);
    return p;
  }();
  return small ? part : full;
}

const KdTree& tree(bool small) {
  static const KdTree full(scan(false));
  static const KdTree part(scan(true));
  return small ? part : full;
}

void set_counters(benchmark::State& st, std::size_t n) {
  st.counters["points"] = double(n);
  st.SetItemsProcessed(int64_t(st.iterations()) * int64_t(n));
}

void BM_KdTreeBuild(benchmark::State& st) {
  const auto& pts = scan(st.range(0) == 780);
  for (auto _ : st) {
    KdTree t(pts);
    benchmark::DoNotOptimize(t.size());
  }
  set_counters(st, pts.size());
}

// The inspection's sort into leaf order with its tree (sort_for_search), on a copy of the scan made untimed.
void BM_SortForSearch(benchmark::State& st) {
  const auto& pts = scan(st.range(0) == 780);
  for (auto _ : st) {
    st.PauseTiming();
    Cloud cloud;
    cloud.points = pts;
    st.ResumeTiming();
    const KdTree t = sort_for_search(cloud);
    benchmark::DoNotOptimize(t.size());
  }
  set_counters(st, pts.size());
}

// The way sort_for_search worked until 2026-12-05, for comparison: the order from the index-only build (its reads
// through the indices are scattered), the positions gathered by it (serially here; that code gathered in parallel),
// then the tree built again over them in place.
void BM_SortThenBuild(benchmark::State& st) {
  const auto& pts = scan(st.range(0) == 780);
  for (auto _ : st) {
    st.PauseTiming();
    std::vector<Eigen::Vector3f> points = pts;
    st.ResumeTiming();
    const std::vector<std::uint32_t> order = spatial_sort_order(points);
    std::vector<Eigen::Vector3f> moved(order.size());
    for (std::size_t j = 0; j < order.size(); ++j) moved[j] = points[order[j]];
    points.swap(moved);
    const KdTree t(points);
    benchmark::DoNotOptimize(t.size());
  }
  set_counters(st, pts.size());
}

void BM_Resolution(benchmark::State& st) {
  const KdTree& t = tree(st.range(0) == 780);
  ResolutionResult r;
  for (auto _ : st) r = spatial_resolution(t);
  st.counters["mean_mm"] = r.mean_mm;
  st.counters["median_mm"] = r.median_mm;
  set_counters(st, t.size());
}

void BM_RadiusOutliersDefault(benchmark::State& st) {
  const KdTree& t = tree(st.range(0) == 780);
  RadiusOutlierResult r;
  for (auto _ : st) r = remove_radius_outliers(t, {});
  st.counters["kept"] = double(r.kept.size());
  st.counters["radius_mm"] = r.radius_mm;
  st.counters["k"] = r.min_neighbors;
  set_counters(st, t.size());
}

void BM_RadiusOutliers_r2_k4(benchmark::State& st) {
  const KdTree& t = tree(st.range(0) == 780);
  RadiusOutlierParams p;
  p.radius_mm = 2.0;
  p.min_neighbors = 4;
  RadiusOutlierResult r;
  for (auto _ : st) r = remove_radius_outliers(t, p);
  st.counters["kept"] = double(r.kept.size());
  set_counters(st, t.size());
}

// As the peers are measured in DESIGN.md: build the tree, then filter.
void BM_RadiusOutliers_r2_k4_WithBuild(benchmark::State& st) {
  const auto& pts = scan(st.range(0) == 780);
  RadiusOutlierParams p;
  p.radius_mm = 2.0;
  p.min_neighbors = 4;
  RadiusOutlierResult r;
  for (auto _ : st) {
    KdTree t(pts);
    r = remove_radius_outliers(t, p);
  }
  st.counters["kept"] = double(r.kept.size());
  set_counters(st, pts.size());
}

void BM_VoxelDownsample_2mm(benchmark::State& st) {
  Cloud c;
  c.points = scan(st.range(0) == 780);
  VoxelGridResult r;
  for (auto _ : st) r = voxel_downsample(c, 2.0);
  st.counters["voxels"] = double(r.cloud.size());
  set_counters(st, c.size());
}

// Clustering of the whole scan at 1 mm (2 x spacing): the outlier-heavy worst case.
void BM_EuclideanClusters_1mm(benchmark::State& st) {
  const KdTree& t = tree(st.range(0) == 780);
  ClusterResult r;
  for (auto _ : st) r = euclidean_clusters(t, {}, 1.0, 1);
  st.counters["clusters"] = double(r.clusters.size());
  st.counters["largest"] = r.clusters.empty() ? 0.0 : double(r.clusters[0].size());
  set_counters(st, t.size());
}

// Clustering after outlier removal, PCL-style limits (min 100 points).
void BM_EuclideanClusters_1mm_Filtered(benchmark::State& st) {
  const KdTree& t = tree(st.range(0) == 780);
  const auto kept = remove_radius_outliers(t, {}).kept;
  ClusterResult r;
  for (auto _ : st) r = euclidean_clusters(t, kept, 1.0, 100);
  st.counters["clusters"] = double(r.clusters.size());
  set_counters(st, kept.size());
}

void BM_Normals_k16(benchmark::State& st) {
  const KdTree& t = tree(st.range(0) == 780);
  std::vector<Eigen::Vector3f> n;
  for (auto _ : st) n = estimate_normals(t, NormalParams{});
  set_counters(st, t.size());
}

}  // namespace

// Arg: 1300 = the full ~1.3 M-point scan; 780 = its ~0.78 M-point part (x < 230 mm).
#define EWIS_BENCH(fn) \
  BENCHMARK(fn)->Arg(780)->Arg(1300)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime()
EWIS_BENCH(BM_KdTreeBuild);
EWIS_BENCH(BM_SortForSearch);
EWIS_BENCH(BM_SortThenBuild);
EWIS_BENCH(BM_Resolution);
EWIS_BENCH(BM_RadiusOutliersDefault);
EWIS_BENCH(BM_RadiusOutliers_r2_k4);
EWIS_BENCH(BM_RadiusOutliers_r2_k4_WithBuild);
EWIS_BENCH(BM_VoxelDownsample_2mm);
EWIS_BENCH(BM_EuclideanClusters_1mm);
EWIS_BENCH(BM_EuclideanClusters_1mm_Filtered);
EWIS_BENCH(BM_Normals_k16);

BENCHMARK_MAIN();
