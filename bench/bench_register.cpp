// Registration benchmarks: point-to-plane ICP of 50 k source points onto 200 k target points (3 deg / 15 mm
// initial error), and global registration (FPFH + RANSAC + ICP) of the same clouds with no pose.
#include <benchmark/benchmark.h>

#include <random>

#include "ewis/register/global_registration.hpp"
#include "ewis/register/icp.hpp"
#include "ewis/sample/mesh_sampling.hpp"
#include "ewis/scene/primitives.hpp"

namespace {

using namespace ewis;

// A CAD-like rigid scene (plate, blocks, L-bracket, connector), sampled area-weighted with triangle normals.
Scene make_scene() {
  using V = Eigen::Vector3d;
  Scene s;
  auto add = [&](const char* name, const Mesh& m) { add_element(s, name, m.vertices, m.triangles); };
  add("plate", make_box(V(0, 0, -5), V(400, 300, 0)));
  add("block_1", make_box(V(40, 40, 0), V(110, 85, 45)));
  add("block_2", make_box(V(250, 190, 0), V(300, 265, 70)));
  add("block_3", make_box(V(300, 30, 0), V(370, 60, 25)));
  add("bracket_a", make_box(V(150, 210, 0), V(156, 270, 60)));
  add("bracket_b", make_box(V(150, 210, 54), V(205, 270, 60)));
  add("connector", make_cylinder(V(200, 80, 0), V(200, 80, 35), 14.0, 48));
  return s;
}

Cloud sample(const Scene& scene, std::size_t n, std::uint64_t seed) {
  double area = 0;
  for (const auto& e : scene.elements) area += e.area_mm2;
  MeshSamplingParams p;
  p.spacing_mm = std::sqrt(area / static_cast<double>(n));
  p.max_points = n;
  p.seed = seed;
  return sample_mesh(scene, p).cloud;
}

struct Data {
  Scene scene = make_scene();
  Cloud target = sample(scene, 200000, 1);
  Cloud source = sample(scene, 50000, 2);
  KdTree tree{target.points};
  Pose truth = make_pose(Eigen::Vector3d(0.3, -0.5, 1.0), 20.0, Eigen::Vector3d(80.0, -100.0, 700.0));
  Data() {
    // The source is a scan in its own frame with 0.2 mm noise along the normal.
    std::mt19937_64 rng(3);
    std::normal_distribution<double> g(0.0, 0.2);
    const Pose to_source = truth.inverse();
    for (std::size_t i = 0; i < source.size(); ++i)
      source.points[i] = (to_source * (source.points[i].cast<double>() + g(rng) * source.normals[i].cast<double>()))
                             .cast<float>();
    source.normals.clear();
  }
};
const Data& data() {
  static const Data d;
  return d;
}

// 3 deg about the scene's centre and 15 mm off (the "3 deg / 15 mm").
Pose initial_pose(const Pose& truth) {
  const Eigen::Vector3d c(200, 150, 20);
  return Eigen::Translation3d(c) * make_pose(Eigen::Vector3d(1, 1, 0), 3.0, Eigen::Vector3d(9, -9, 7.5)) *
         Eigen::Translation3d(-c) * truth;
}

void BM_Icp50kOnto200k(benchmark::State& state) {
  const Data& d = data();
  // Initial pose 3 deg / 15 mm off the truth.
  const Pose init = initial_pose(d.truth);
  IcpParams p;
  p.expected_error_mm = 15.0;
  RegistrationResult r;
  for (auto _ : state) {
    r = align_point_to_plane(d.source.points, d.target, d.tree, init, p);
    benchmark::DoNotOptimize(r);
  }
  state.counters["iterations"] = r.iterations;
  state.counters["rot_err_deg"] = rotation_error_deg(r.source_to_target, d.truth);
  state.counters["trans_err_mm"] = translation_error_mm(r.source_to_target, d.truth);
  state.counters["fitness"] = r.fitness;
}
BENCHMARK(BM_Icp50kOnto200k)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_GlobalNoPose(benchmark::State& state) {
  const Data& d = data();
  GlobalRegistrationResult r;
  for (auto _ : state) {
    r = register_global(d.source, d.target);
    benchmark::DoNotOptimize(r);
  }
  state.counters["valid"] = r.valid;
  state.counters["rot_err_deg"] = rotation_error_deg(r.registration.source_to_target, d.truth);
  state.counters["trans_err_mm"] = translation_error_mm(r.registration.source_to_target, d.truth);
  state.counters["voxel_mm"] = r.voxel_mm;
}
BENCHMARK(BM_GlobalNoPose)->Unit(benchmark::kMillisecond)->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
