// Segmentation time per metre of cable (issue 5; paper 4.3.1 "almost immediate"): trace_tube on a
// simulated scan (sensor at the origin, 0.5 mm spacing, 0.2 mm noise, 40% outliers) of a small harness.
#include <benchmark/benchmark.h>

#include "../tests/tubes/synthetic_scan.hpp"
#include "ewis/search/kdtree.hpp"
#include "ewis/tubes/trace.hpp"

namespace {

using Eigen::Vector3d;

struct Harness {
  synth::Scan scan;
  std::vector<Vector3d> seeds;
  double length_mm = 0;
};

// Three cables (diameters 5, 10, 20 mm), each with a bend, ~0.9 m in all.
const Harness& harness() {
  static const Harness h = [] {
    Harness out;
    synth::Scene scene;
    const double radii[] = {2.5, 5.0, 10.0};
    for (int k = 0; k < 3; ++k) {
      const double r = radii[k], R = 60.0, y0 = -60.0 + 60.0 * k;
      std::vector<Vector3d> line;
      for (const auto& p : synth::line(Vector3d(-150, y0, 620), Vector3d(0, y0, 620))) line.push_back(p);
      for (const auto& p : synth::curve([&](double a) { return Vector3d(R * std::sin(a), y0, 620 + R - R * std::cos(a)); }, 0,
                                        M_PI / 2, 200))
        line.push_back(p);
      for (const auto& p : synth::line(Vector3d(R, y0, 620 + R), Vector3d(R, y0, 620 + R + 60))) line.push_back(p);
      scene.add_tube(line, r, k);
      out.seeds.push_back(Vector3d(-75, y0, 620 - r));
      out.length_mm += synth::distance_to_polyline(line, line.front()) + 150 + R * M_PI / 2 + 60;
    }
    out.scan = synth::render(scene);
    return out;
  }();
  return h;
}

void BM_TraceHarness(benchmark::State& state) {
  const Harness& h = harness();
  const ewis::KdTree tree(h.scan.cloud.points);
  double traced = 0;
  for (auto _ : state) {
    traced = 0;
    for (const Vector3d& s : h.seeds) {
      const ewis::TubeTrace t = ewis::trace_tube(h.scan.cloud, tree, s, {});
      traced += t.length_mm;
      benchmark::DoNotOptimize(t.points.data());
    }
  }
  state.counters["traced_mm"] = traced;
  state.counters["points"] = static_cast<double>(h.scan.cloud.size());
  // seconds per traced metre (wall clock)
  state.counters["s_per_m"] = benchmark::Counter(traced / 1000.0, benchmark::Counter::kIsIterationInvariantRate |
                                                                      benchmark::Counter::kInvert);
}
BENCHMARK(BM_TraceHarness)->Unit(benchmark::kMillisecond);

void BM_KdTreeBuild(benchmark::State& state) {
  const Harness& h = harness();
  for (auto _ : state) {
    ewis::KdTree tree(h.scan.cloud.points);
    benchmark::DoNotOptimize(&tree);
  }
}
BENCHMARK(BM_KdTreeBuild)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
