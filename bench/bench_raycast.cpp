// Raycast throughput on a ~100k-triangle wiring scene: full 1280x1024 renders with single rays and
// 4/8/16-ray packets, the element pixel count of viewpoint scoring, and the BVH build.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <cmath>

#include "ewis/raycast/raycaster.hpp"
#include "ewis/scene/primitives.hpp"

namespace {

using Eigen::Vector3d;

const ewis::Scene& wiring_scene() {
  static const ewis::Scene scene = [] {
    ewis::Scene s;
    const ewis::Mesh floor = ewis::make_box(Vector3d(-600, -600, -30), Vector3d(600, 600, 0));
    ewis::add_element(s, "structure", floor.vertices, floor.triangles);
    // 40 cables of 60 centreline points x 16 segments, wavy and at several heights.
    for (int c = 0; c < 40; ++c) {
      std::vector<Vector3d> line;
      for (int k = 0; k < 60; ++k) {
        const double t = k / 59.0;
        line.emplace_back(-500 + 1000 * t, -480 + 24.0 * c + 15 * std::sin(6 * t + c), 20 + 10 * (c % 5) + 8 * std::cos(9 * t));
      }
      const ewis::Mesh tube = ewis::make_tube(line, 4 + (c % 3), 16);
      ewis::add_element(s, "cable_" + std::to_string(c), tube.vertices, tube.triangles);
    }
    // Brackets and clamps.
    for (int b = 0; b < 60; ++b) {
      const Vector3d lo(-480 + 16.0 * b, -500 + 17.0 * (b % 7) * 8, 0);
      const ewis::Mesh box = ewis::make_box(lo, lo + Vector3d(10, 30, 80));
      ewis::add_element(s, "bracket_" + std::to_string(b), box.vertices, box.triangles);
    }
    // Fill up with a finely tessellated cylinder so the total is ~100k triangles.
    const ewis::Mesh pipe = ewis::make_tube({Vector3d(-550, 550, 60), Vector3d(550, 550, 60)}, 25, 2048);
    std::vector<Vector3d> rail;
    for (int k = 0; k < 400; ++k) rail.emplace_back(-550 + 1100.0 * k / 399, -560, 40);
    const ewis::Mesh r = ewis::make_tube(rail, 12, 24);
    ewis::add_element(s, "pipe", pipe.vertices, pipe.triangles);
    ewis::add_element(s, "rail", r.vertices, r.triangles);
    return s;
  }();
  return scene;
}

ewis::Pose view() { return ewis::look_at(Vector3d(0, -700, 700), Vector3d(0, -50, 0)); }

void BM_Render(benchmark::State& state) {
  const ewis::Raycaster rc(wiring_scene(), {}, static_cast<int>(state.range(0)));
  const ewis::Camera cam;  // 1280 x 1024
  std::size_t hits = 0;
  for (auto _ : state) {
    const ewis::Render img = ewis::render(rc, cam, view());
    hits = 0;
    for (std::uint32_t e : img.element) hits += e != ewis::kNoElement;
    benchmark::DoNotOptimize(hits);
  }
  const double rays = double(cam.width_px) * cam.height_px;
  state.counters["Mrays"] = benchmark::Counter(rays * state.iterations() / 1e6, benchmark::Counter::kIsRate);
  state.counters["hit_fraction"] = double(hits) / rays;
  state.counters["triangles"] = double(wiring_scene().triangle_count());
}
BENCHMARK(BM_Render)->Arg(1)->Arg(4)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond)->UseRealTime();

// One thread, rate per CPU second: comparable across machines and robust to other load on the machine.
void BM_RenderOneThread(benchmark::State& state) {
  const ewis::Raycaster rc(wiring_scene(), {}, static_cast<int>(state.range(0)));
  const ewis::Camera cam;
  tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  for (auto _ : state) {
    const ewis::Render img = ewis::render(rc, cam, view());
    benchmark::DoNotOptimize(img.element.data());
  }
  state.counters["Mrays"] = benchmark::Counter(double(cam.width_px) * cam.height_px * state.iterations() / 1e6,
                                               benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RenderOneThread)->Arg(1)->Arg(8)->Arg(16)->Unit(benchmark::kMillisecond);

void BM_CountElementPixels(benchmark::State& state) {
  const ewis::Raycaster rc(wiring_scene());
  const ewis::Camera cam;
  const std::uint32_t element = static_cast<std::uint32_t>(wiring_scene().find("cable_20"));
  std::size_t pixels = 0;
  for (auto _ : state) {
    pixels = ewis::count_element_pixels(rc, cam, view(), element);
    benchmark::DoNotOptimize(pixels);
  }
  state.counters["pixels"] = double(pixels);
}
BENCHMARK(BM_CountElementPixels)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_CountSmallElementPixels(benchmark::State& state) {
  const ewis::Raycaster rc(wiring_scene());
  const ewis::Camera cam;
  const std::uint32_t element = static_cast<std::uint32_t>(wiring_scene().find("bracket_30"));
  std::size_t pixels = 0;
  for (auto _ : state) {
    pixels = ewis::count_element_pixels(rc, cam, view(), element);
    benchmark::DoNotOptimize(pixels);
  }
  state.counters["pixels"] = double(pixels);
}
BENCHMARK(BM_CountSmallElementPixels)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_BuildBvh(benchmark::State& state) {
  for (auto _ : state) {
    const ewis::Raycaster rc(wiring_scene());
    benchmark::DoNotOptimize(&rc);
  }
}
BENCHMARK(BM_BuildBvh)->Unit(benchmark::kMillisecond)->UseRealTime();

// Incoherent rays (random directions from scattered origins) through the batch API.
void BM_BatchIncoherent(benchmark::State& state) {
  const ewis::Raycaster rc(wiring_scene(), {}, static_cast<int>(state.range(0)));
  std::vector<ewis::Ray> rays(1 << 20);
  std::uint64_t x = 12345;
  auto next = [&] {
    x = x * 6364136223846793005ull + 1442695040888963407ull;
    return float((x >> 33) & 0xFFFFFF) / float(0x1000000) * 2.f - 1.f;
  };
  for (auto& r : rays) {
    r.origin = Eigen::Vector3f(next() * 500, next() * 500, 200 + next() * 100);
    r.direction = Eigen::Vector3f(next(), next(), next() - 0.5f);
  }
  std::vector<ewis::Hit> hits;
  for (auto _ : state) {
    rc.cast(rays, hits);
    benchmark::DoNotOptimize(hits.data());
  }
  state.counters["Mrays"] = benchmark::Counter(double(rays.size()) * state.iterations() / 1e6,
                                                 benchmark::Counter::kIsRate);
}
BENCHMARK(BM_BatchIncoherent)->Arg(1)->Arg(16)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
