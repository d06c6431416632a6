// The steps of bench/compare.sh through Open3D 0.16, each with its nearest Open3D equivalent and the same parameters.
#include <open3d/Open3D.h>

#include <string>

#include "steps_common.hpp"

using open3d::geometry::PointCloud;

static std::shared_ptr<PointCloud> load(const std::string& path) {
  auto cloud = std::make_shared<PointCloud>();
  if (!open3d::io::ReadPointCloud(path, *cloud)) throw std::runtime_error("cannot read " + path);
  return cloud;
}

int main(int argc, char** argv) {
  open3d::utility::SetVerbosityLevel(open3d::utility::VerbosityLevel::Error);
  if (argc < 3) return steps::usage(argv[0]);
  const std::string step = argv[1], file = argv[2];
  if (step == "read") {
    steps::Timer t;
    auto cloud = load(file);
    steps::print(step, t.ms(), double(cloud->points_.size()));
    return 0;
  }
  if (step == "sample" && argc >= 4) {
    auto mesh = std::make_shared<open3d::geometry::TriangleMesh>();
    open3d::io::ReadTriangleMesh(file, *mesh);
    steps::Timer t;
    auto pts = mesh->SamplePointsUniformly(std::stoul(argv[3]));
    steps::print(step, t.ms(), double(pts->points_.size()));
    return 0;
  }
  auto cloud = load(file);
  const std::size_t n = cloud->points_.size();
  if (step == "resolution") {
    steps::Timer t;
    open3d::geometry::KDTreeFlann tree(*cloud);
    std::vector<int> idx;
    std::vector<double> d2;
    double sum = 0;
    for (std::size_t i = 0; i < n; ++i) {
      tree.SearchKNN(cloud->points_[i], 2, idx, d2);
      sum += std::sqrt(d2[1]);
    }
    steps::print(step, t.ms(), sum / n);
  } else if (step == "ror" && argc >= 5) {
    steps::Timer t;
    // Open3D keeps a point whose radius search (which includes the point itself) finds more than nb_points.
    auto [out, kept] = cloud->RemoveRadiusOutliers(std::stoul(argv[4]), std::stod(argv[3]));
    const double ms = t.ms();
    unsigned long long checksum = 0;
    for (auto i : kept) checksum += static_cast<unsigned long long>(i);
    steps::print(step, ms, double(kept.size()), "index_sum=" + std::to_string(checksum));
  } else if (step == "voxel" && argc >= 4) {
    steps::Timer t;
    auto out = cloud->VoxelDownSample(std::stod(argv[3]));
    steps::print(step, t.ms(), double(out->points_.size()));
  } else if (step == "cluster" && argc >= 4) {
    steps::Timer t;
    auto labels = cloud->ClusterDBSCAN(std::stod(argv[3]), 1);
    const double ms = t.ms();
    int clusters = 0;
    for (int l : labels) clusters = std::max(clusters, l + 1);
    steps::print(step, ms, double(clusters));
  } else {
    return steps::usage(argv[0]);
  }
  return 0;
}
