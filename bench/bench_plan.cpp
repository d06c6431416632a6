// Viewpoint scoring speed (issue 7): all 648 candidates of a 10-degree step at 1280x1024 over a ~100 k-triangle
// scene of tubes (cables) and boxes (brackets, structure). Numbers go to bench/RESULTS.md.
#include <benchmark/benchmark.h>

#include <cmath>

#include "ewis/plan/candidates.hpp"
#include "ewis/plan/score.hpp"
#include "ewis/plan/viewpoint_plan.hpp"
#include "ewis/scene/primitives.hpp"

namespace {

using namespace ewis;

void add(Scene& s, const std::string& name, const Mesh& m) { add_element(s, name, m.vertices, m.triangles); }

// A harness bay: a floor, frames, clamps, a pipe ring and 24 wavy cables of 500 mm; ~100 k triangles.
const Scene& bay() {
  static const Scene scene = [] {
    Scene s;
    add(s, "floor", make_box({-600, -400, -20}, {600, 400, 0}));
    for (int i = 0; i < 6; ++i)
      add(s, "frame_" + std::to_string(i), make_box({-500.0 + 200 * i, -400, 0}, {-480.0 + 200 * i, 400, 250}));
    for (int c = 0; c < 24; ++c) {
      std::vector<Eigen::Vector3d> line;
      const double x0 = (c % 2 == 0) ? -550 : 50;
      for (int k = 0; k <= 110; ++k) {
        const double x = x0 + 500.0 * k / 110;
        line.emplace_back(x, -300 + 50.0 * (c / 2) + 15 * std::sin(x / 90.0 + c), 120 + 30 * std::sin(x / 140.0 + 0.5 * c));
      }
      add(s, "cable_" + std::to_string(c), make_tube(line, 4.0 + 0.5 * (c % 4), 16));
    }
    for (int b = 0; b < 20; ++b) {
      const double x = -550 + 55.0 * b;
      add(s, "clamp_" + std::to_string(b), make_cylinder({x, -320, 120}, {x, 320, 120}, 3.0, 24));
    }
    add(s, "pipe", make_torus({0, 0, 200}, {0, 0, 1}, 250, 12, 192, 48));
    return s;
  }();
  return scene;
}

void BM_Score648Candidates(benchmark::State& state) {
  const Scene& scene = bay();
  const std::uint32_t element = static_cast<std::uint32_t>(scene.find("cable_12"));
  const Raycaster all(scene);
  const Camera camera{1280, 1024, 58.0};
  const CandidateGrid grid = make_candidates(scene.elements[element].center_of_mass, CandidateParams{});
  ScoreParams params;
  params.measurable = state.range(0) != 0;
  std::uint64_t best = 0;
  for (auto _ : state) {
    const auto scores = score_candidates(all, camera, element, grid.candidates, 600.0, params);
    for (const auto& s : scores) best = std::max(best, s.score_px);
    benchmark::DoNotOptimize(best);
  }
  state.counters["triangles"] = double(scene.triangle_count());
  state.counters["candidates"] = double(grid.candidates.size());
  state.counters["best_px"] = double(best);
}
BENCHMARK(BM_Score648Candidates)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// The whole `ewis plan` for one element: 648 scores, the top 5 with visible_fraction (no pictures).
void BM_PlanOneElement(benchmark::State& state) {
  const Scene& scene = bay();
  const std::uint32_t element = static_cast<std::uint32_t>(scene.find("cable_12"));
  SensorModel sensor;
  for (auto _ : state) {
    const ViewpointPlan plan = plan_viewpoints(scene, sensor, {element}, ViewpointParams{});
    benchmark::DoNotOptimize(plan.best.size());
  }
}
BENCHMARK(BM_PlanOneElement)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

void BM_CoverAllCables(benchmark::State& state) {
  const Scene& scene = bay();
  std::vector<std::uint32_t> cables;
  for (int c = 0; c < 24; c += 6) cables.push_back(static_cast<std::uint32_t>(scene.find("cable_" + std::to_string(c))));
  SensorModel sensor;
  ViewpointParams params;
  params.candidates.step_deg = 20;
  std::size_t size = 0;
  for (auto _ : state) {
    const ViewpointPlan plan = plan_viewpoints(scene, sensor, cables, params);
    size = plan.coverage.viewpoints.size();
  }
  state.counters["set_size"] = double(size);
}
BENCHMARK(BM_CoverAllCables)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
