// Scan time of the virtual sensor on a full 1280x1024 generated scene (issue 3: "well under a second").
#include <benchmark/benchmark.h>

#include "ewis/raycast/raycaster.hpp"
#include "ewis/sim/scene_generator.hpp"
#include "ewis/sim/sensor.hpp"

using namespace ewis;
using namespace ewis::sim;

namespace {

struct Fixture {
  SimScene sim;
  Scene built;
  Fixture() {
    SceneParams p;
    p.seed = 7;
    p.cables = 3;
    p.pipes = 2;
    sim = generate_scene(p);
    built = as_built_scene(sim);
  }
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

void BM_GenerateScene(benchmark::State& state) {
  std::uint64_t seed = 1;
  for (auto _ : state) {
    SceneParams p;
    p.seed = seed++;
    p.defect = DefectKind::Random;
    benchmark::DoNotOptimize(generate_scene(p));
  }
}
BENCHMARK(BM_GenerateScene)->Unit(benchmark::kMillisecond);

void BM_BuildRaycaster(benchmark::State& state) {
  const Fixture& f = fixture();
  for (auto _ : state) benchmark::DoNotOptimize(Raycaster(f.built));
  state.counters["triangles"] = double(f.built.triangle_count());
}
BENCHMARK(BM_BuildRaycaster)->Unit(benchmark::kMillisecond);

// The full scan: camera rays, projector (shadow) rays, noise, 40% outliers (arg 1) or noise-free (arg 0).
void BM_Scan1280x1024(benchmark::State& state) {
  const Fixture& f = fixture();
  const Raycaster caster(f.built);
  SensorParams sp;
  sp.noise_free = state.range(0) == 0;
  std::size_t points = 0;
  for (auto _ : state) {
    const ScanResult r = scan(caster, f.sim.sensor.camera(), f.sim.camera_to_cad, sp);
    points = r.cloud.size();
    benchmark::DoNotOptimize(r.cloud.points.data());
  }
  state.counters["points"] = double(points);
  state.counters["triangles"] = double(f.built.triangle_count());
  state.counters["Mrays/s"] = benchmark::Counter(2.0 * 1280 * 1024 * state.iterations() / 1e6, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Scan1280x1024)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
