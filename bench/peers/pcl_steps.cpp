// The steps of bench/compare.sh through PCL 1.13, each with its nearest PCL equivalent and the same parameters.
#include <pcl/filters/radius_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

#include <string>

#include "steps_common.hpp"

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

static bool ends_with(const std::string& s, const std::string& e) {
  return s.size() >= e.size() && s.compare(s.size() - e.size(), e.size(), e) == 0;
}

static Cloud::Ptr load(const std::string& path) {
  Cloud::Ptr cloud(new Cloud);
  const int rc = ends_with(path, ".pcd") ? pcl::io::loadPCDFile(path, *cloud) : pcl::io::loadPLYFile(path, *cloud);
  if (rc < 0) throw std::runtime_error("cannot read " + path);
  return cloud;
}

int main(int argc, char** argv) {
  if (argc < 3) return steps::usage(argv[0]);
  const std::string step = argv[1], file = argv[2];
  if (step == "read") {
    steps::Timer t;
    auto cloud = load(file);
    steps::print(step, t.ms(), double(cloud->size()));
    return 0;
  }
  auto cloud = load(file);
  if (step == "resolution") {
    steps::Timer t;
    pcl::KdTreeFLANN<pcl::PointXYZ> tree;
    tree.setInputCloud(cloud);
    std::vector<int> idx(2);
    std::vector<float> d2(2);
    double sum = 0;
    for (std::size_t i = 0; i < cloud->size(); ++i) {
      tree.nearestKSearch((*cloud)[i], 2, idx, d2);
      sum += std::sqrt(d2[1]);
    }
    steps::print(step, t.ms(), sum / cloud->size());
  } else if (step == "ror" && argc >= 5) {
    steps::Timer t;
    pcl::RadiusOutlierRemoval<pcl::PointXYZ> ror;
    ror.setInputCloud(cloud);
    ror.setRadiusSearch(std::stod(argv[3]));
    ror.setMinNeighborsInRadius(std::stoi(argv[4]));  // PCL counts the query point itself: k <= min is removed
    pcl::Indices kept;
    ror.filter(kept);
    const double ms = t.ms();
    unsigned long long checksum = 0;
    for (auto i : kept) checksum += static_cast<unsigned long long>(i);
    steps::print(step, ms, double(kept.size()), "index_sum=" + std::to_string(checksum));
  } else if (step == "voxel" && argc >= 4) {
    steps::Timer t;
    pcl::VoxelGrid<pcl::PointXYZ> grid;
    const float leaf = std::stof(argv[3]);
    grid.setInputCloud(cloud);
    grid.setLeafSize(leaf, leaf, leaf);
    Cloud out;
    grid.filter(out);
    steps::print(step, t.ms(), double(out.size()));
  } else if (step == "cluster" && argc >= 4) {
    steps::Timer t;
    pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
    tree->setInputCloud(cloud);
    pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
    ec.setClusterTolerance(std::stod(argv[3]));
    ec.setMinClusterSize(1);
    ec.setMaxClusterSize(std::numeric_limits<int>::max());
    ec.setSearchMethod(tree);
    ec.setInputCloud(cloud);
    std::vector<pcl::PointIndices> clusters;
    ec.extract(clusters);
    steps::print(step, t.ms(), double(clusters.size()),
                 "largest=" + std::to_string(clusters.empty() ? 0 : clusters.front().indices.size()));
  } else {
    return steps::usage(argv[0]);
  }
  return 0;
}
