// Benchmarks of the inspect stage's measuring core (the whole `ewis inspect` is timed per step on stderr).
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "ewis/inspect/bend_radius.hpp"
#include "ewis/scene/surface_index.hpp"
#include "ewis/scene/primitives.hpp"

using namespace ewis;

namespace {

// 150 mm straight, 90 deg arc of radius 50, 150 mm straight; a point per mm, 0.1 mm noise.
std::vector<Eigen::Vector3d> bend_centerline() {
  std::vector<Eigen::Vector3d> pts;
  std::mt19937_64 rng(1);
  std::normal_distribution<double> n(0.0, 0.1);
  auto add = [&](const Eigen::Vector3d& p) { pts.push_back(p + Eigen::Vector3d(n(rng), n(rng), n(rng))); };
  for (int i = 0; i <= 150; ++i) add({double(i), 0, 0});
  for (int i = 1; i <= 78; ++i) {
    const double a = (M_PI / 2) * i / 78.0;
    add({150 + 50 * std::sin(a), 50 - 50 * std::cos(a), 0});
  }
  for (int i = 1; i <= 150; ++i) add({200, 50.0 + i, 0});
  return pts;
}

void BM_BendRadius(benchmark::State& state) {
  const auto pts = bend_centerline();
  for (auto _ : state) benchmark::DoNotOptimize(measure_bend_radius(pts, 10.0));
}
BENCHMARK(BM_BendRadius)->Unit(benchmark::kMillisecond);

void BM_SurfaceClosest(benchmark::State& state) {
  Scene scene;
  const Mesh torus = make_torus({0, 0, 0}, {0, 0, 1}, 100, 20, 256, 64);
  add_element(scene, "torus", torus.vertices, torus.triangles);
  const SurfaceIndex idx(scene, {0});
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(-130, 130);
  std::vector<Eigen::Vector3d> q(4096);
  for (auto& p : q) p = {u(rng), u(rng), u(rng) * 0.3};
  for (auto _ : state)
    for (const auto& p : q) benchmark::DoNotOptimize(idx.closest(p, 3.0));
  state.SetItemsProcessed(state.iterations() * q.size());
}
BENCHMARK(BM_SurfaceClosest)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
