// The steps of bench/compare.sh through ewis, timed the same way as pcl_steps and open3d_steps (input loading is
// outside the timer except for the read steps; k-d tree builds are inside, as for the peers).
#include <string>

#include "ewis/core/error.hpp"
#include "ewis/filter/euclidean_clusters.hpp"
#include "ewis/filter/outlier_removal.hpp"
#include "ewis/filter/resolution.hpp"
#include "ewis/filter/voxel_grid.hpp"
#include "ewis/io/cloud_io.hpp"
#include "ewis/sample/mesh_sampling.hpp"
#include "ewis/scene/scene.hpp"
#include "ewis/search/kdtree.hpp"
#include "steps_common.hpp"

using namespace ewis;

int main(int argc, char** argv) try {
  if (argc < 3) return steps::usage(argv[0]);
  const std::string step = argv[1], file = argv[2];
  if (step == "read") {
    steps::Timer t;
    const CloudFile f = read_cloud(file);
    steps::print(step, t.ms(), double(f.cloud.size()));
    return 0;
  }
  if (step == "convert-pcd" && argc >= 4) {  // helper for compare.sh: a binary_compressed copy of a cloud
    write_pcd(read_cloud(file).cloud, argv[3], true);
    return 0;
  }
  if (step == "sample" && argc >= 4) {
    const Scene scene = load_scene(file);
    steps::Timer t;
    double area = 0;
    for (const auto& e : scene.elements) area += e.area_mm2;
    MeshSamplingParams params;
    params.spacing_mm = std::sqrt(area / std::stod(argv[3]));
    const MeshSamples s = sample_mesh(scene, params);
    steps::print(step, t.ms(), double(s.cloud.size()));
    return 0;
  }
  const CloudFile f = read_cloud(file);
  if (step == "resolution") {
    steps::Timer t;
    const KdTree tree(f.cloud.points);
    const double r = spatial_resolution(tree).mean_mm;
    steps::print(step, t.ms(), r);
  } else if (step == "ror" && argc >= 5) {
    steps::Timer t;
    const KdTree tree(f.cloud.points);
    RadiusOutlierParams params;
    params.radius_mm = std::stod(argv[3]);
    params.min_neighbors = std::stoi(argv[4]);
    const RadiusOutlierResult r = remove_radius_outliers(tree, params);
    const double ms = t.ms();
    unsigned long long checksum = 0;
    for (auto i : r.kept) checksum += i;
    steps::print(step, ms, double(r.kept.size()), "index_sum=" + std::to_string(checksum));
  } else if (step == "voxel" && argc >= 4) {
    steps::Timer t;
    const VoxelGridResult r = voxel_downsample(f.cloud, std::stod(argv[3]));
    steps::print(step, t.ms(), double(r.cloud.size()));
  } else if (step == "cluster" && argc >= 4) {
    steps::Timer t;
    const KdTree tree(f.cloud.points);
    const ClusterResult r = euclidean_clusters(tree, {}, std::stod(argv[3]), 1);
    steps::print(step, t.ms(), double(r.clusters.size()),
                 "largest=" + std::to_string(r.clusters.empty() ? 0 : r.clusters.front().size()));
  } else {
    return steps::usage(argv[0]);
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "ewis_steps: %s\n", e.what());
  return 2;
}
