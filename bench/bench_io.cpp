// read_cloud on a 1.3 M-point binary PLY and a binary_compressed PCD (DESIGN.md "Numbers to beat":
// PCL 74 / 26 ms, Open3D 50 / 11 ms). The files are generated once in /tmp.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "ewis/io/cloud_io.hpp"

namespace {

constexpr std::size_t kPoints = 1300000;

// A wavy surface of 1.3 M points in mm, like a structured-light scan (deterministic).
ewis::Cloud make_scan(bool with_normals) {
  ewis::Cloud c;
  c.points.reserve(kPoints);
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(0.0f, 0.2f);
  const std::size_t side = 1141;  // ~1.3 M
  for (std::size_t i = 0; c.points.size() < kPoints; ++i) {
    const float u = float(i % side), v = float(i / side);
    c.points.emplace_back(u * 0.5f, v * 0.5f, 600.0f + 20.0f * std::sin(u * 0.01f) * std::cos(v * 0.013f) + noise(rng));
    if (with_normals) c.normals.emplace_back(0.0f, 0.0f, 1.0f);
  }
  return c;
}

const std::string& ply_xyz() {
  static const std::string p = [] {
    const std::string path = "/tmp/ewis_bench_io_1p3M.ply";
    if (!std::filesystem::exists(path)) ewis::write_ply(make_scan(false), path);
    return path;
  }();
  return p;
}

const std::string& ply_normals() {
  static const std::string p = [] {
    const std::string path = "/tmp/ewis_bench_io_1p3M_normals.ply";
    if (!std::filesystem::exists(path)) ewis::write_ply(make_scan(true), path);
    return path;
  }();
  return p;
}

const std::string& pcd(bool compressed) {
  static const std::string pc = [] {
    const std::string path = "/tmp/ewis_bench_io_1p3M_compressed.pcd";
    if (!std::filesystem::exists(path)) ewis::write_pcd(make_scan(false), path, true);
    return path;
  }();
  static const std::string pb = [] {
    const std::string path = "/tmp/ewis_bench_io_1p3M_binary.pcd";
    if (!std::filesystem::exists(path)) ewis::write_pcd(make_scan(false), path, false);
    return path;
  }();
  return compressed ? pc : pb;
}

void run(benchmark::State& state, const std::string& path) {
  std::size_t n = 0;
  for (auto _ : state) {
    const ewis::CloudFile f = ewis::read_cloud(path);
    n = f.cloud.size();
    benchmark::DoNotOptimize(f.cloud.points.data());
  }
  state.counters["points"] = double(n);
  state.SetItemsProcessed(state.iterations() * std::int64_t(n));
}

void BM_ReadPlyBinaryXyz(benchmark::State& s) { run(s, ply_xyz()); }
void BM_ReadPlyBinaryXyzNormals(benchmark::State& s) { run(s, ply_normals()); }
void BM_ReadPcdBinary(benchmark::State& s) { run(s, pcd(false)); }
void BM_ReadPcdBinaryCompressed(benchmark::State& s) { run(s, pcd(true)); }

void BM_WritePlyBinary(benchmark::State& s) {
  const ewis::Cloud c = make_scan(false);
  for (auto _ : s) ewis::write_ply(c, "/tmp/ewis_bench_io_write.ply");
  s.SetItemsProcessed(s.iterations() * std::int64_t(c.size()));
}
void BM_WritePcdCompressed(benchmark::State& s) {
  const ewis::Cloud c = make_scan(false);
  for (auto _ : s) ewis::write_pcd(c, "/tmp/ewis_bench_io_write.pcd", true);
  s.SetItemsProcessed(s.iterations() * std::int64_t(c.size()));
}

}  // namespace

BENCHMARK(BM_ReadPlyBinaryXyz)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadPlyBinaryXyzNormals)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadPcdBinary)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ReadPcdBinaryCompressed)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WritePlyBinary)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WritePcdCompressed)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
