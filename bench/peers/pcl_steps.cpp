// The steps of bench/compare.sh through PCL 1.13, each with its nearest PCL equivalent and the same parameters.
#include <pcl/features/normal_3d_omp.h>
#include <pcl/filters/radius_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>
#include <pcl/common/transforms.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>
#include <pcl/segmentation/sac_segmentation.h>

#include <map>
#include <string>

#include "steps_common.hpp"

using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using NormalCloud = pcl::PointCloud<pcl::PointNormal>;

static bool ends_with(const std::string& s, const std::string& e) {
  return s.size() >= e.size() && s.compare(s.size() - e.size(), e.size(), e) == 0;
}

static Cloud::Ptr load(const std::string& path) {
  Cloud::Ptr cloud(new Cloud);
  const int rc = ends_with(path, ".pcd") ? pcl::io::loadPCDFile(path, *cloud) : pcl::io::loadPLYFile(path, *cloud);
  if (rc < 0) throw std::runtime_error("cannot read " + path);
  return cloud;
}

static std::vector<Eigen::Vector3d> to_double(const Cloud& cloud) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : cloud) out.emplace_back(p.x, p.y, p.z);
  return out;
}

// IterativeClosestPointWithNormals with its iteration count visible.
struct Icp : pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal> {
  int iterations() const { return nr_iterations_; }
};

// Point-to-plane ICP (PCL's linear least squares, no robust kernel) over the shared distance schedule from
// first_distance_mm; returns the pose and adds the iterations run.
static Eigen::Matrix4d align(const Cloud& source_xyz, const NormalCloud::Ptr& target, const Eigen::Matrix4d& init,
                             double first_distance_mm, int& iterations) {
  NormalCloud::Ptr source(new NormalCloud);
  pcl::copyPointCloud(source_xyz, *source);  // normals 0: point-to-plane uses the target's only
  Icp icp;
  icp.setInputSource(source);
  icp.setInputTarget(target);
  pcl::search::KdTree<pcl::PointNormal>::Ptr tree(new pcl::search::KdTree<pcl::PointNormal>);
  tree->setInputCloud(target);
  icp.setSearchMethodTarget(tree, true);  // one target k-d tree for all stages (align() would rebuild it)
  icp.setMaximumIterations(steps::kIcpIterationsPerStage);
  icp.setTransformationEpsilon(1e-8);  // the update-size test of ewis: 1e-4 mm (squared here) ...
  icp.setTransformationRotationEpsilon(std::cos(1e-4 * M_PI / 180.0));  // ... and 1e-4 deg
  Eigen::Matrix4f pose = init.cast<float>();
  NormalCloud aligned;
  for (double d : steps::icp_schedule_mm(first_distance_mm)) {
    icp.setMaxCorrespondenceDistance(d);
    icp.align(aligned, pose);
    pose = icp.getFinalTransformation();
    iterations += icp.iterations();
  }
  return pose.cast<double>();
}

static NormalCloud::Ptr load_with_normals(const std::string& path) {
  NormalCloud::Ptr cloud(new NormalCloud);
  if (pcl::io::loadPLYFile(path, *cloud) < 0) throw std::runtime_error("cannot read " + path);
  return cloud;
}

static int icp_step(const Cloud::Ptr& source, const std::string& target_file, const std::string& init_file,
                    const std::string& truth_file) {
  const NormalCloud::Ptr target = load_with_normals(target_file);
  const Eigen::Matrix4d init = steps::read_matrix4(init_file), truth = steps::read_matrix4(truth_file);
  steps::Timer t;
  int iterations = 0;
  const Eigen::Matrix4d pose = align(*source, target, init, steps::kIcpFirstDistanceMm, iterations);
  const double ms = t.ms();
  pcl::KdTreeFLANN<pcl::PointNormal> tree;
  tree.setInputCloud(target);
  std::vector<int> idx(1);
  std::vector<float> d2(1);
  const std::vector<Eigen::Vector3d> src = to_double(*source);
  const steps::IcpFit fit = steps::icp_fit(src, pose, [&](const Eigen::Vector3d& p, Eigen::Vector3d& q,
                                                           Eigen::Vector3d& n) {
    pcl::PointNormal query;
    query.x = float(p.x()), query.y = float(p.y()), query.z = float(p.z());
    if (tree.nearestKSearch(query, 1, idx, d2) < 1) return false;
    const pcl::PointNormal& m = (*target)[idx[0]];
    q = Eigen::Vector3d(m.x, m.y, m.z);
    n = Eigen::Vector3d(m.normal_x, m.normal_y, m.normal_z);
    return true;
  });
  steps::print("icp", ms, fit.rmse_mm, steps::icp_detail(pose, truth, src, fit, iterations));
  return 0;
}

// One cylinder by RANSAC on points with normals: PCL's SACSegmentationFromNormals, normals (OpenMP, `threads`)
// inside the timer. `viewpoint`: where the normals are turned to (the sensor).
struct CylinderFit {
  bool ok = false;
  Eigen::Vector3d point, axis;
  double radius_mm = 0;
  pcl::Indices inliers;
};
static CylinderFit fit_cylinder(const Cloud::Ptr& cloud, const pcl::search::KdTree<pcl::PointXYZ>::Ptr& tree,
                                const pcl::IndicesPtr& indices, double min_radius_mm, double max_radius_mm,
                                double threshold_mm, int k_normals, const Eigen::Vector3f& viewpoint,
                                int max_iterations, int threads) {
  pcl::PointCloud<pcl::Normal>::Ptr normals(new pcl::PointCloud<pcl::Normal>);
  pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::Normal> ne(threads);
  ne.setSearchMethod(tree);
  ne.setInputCloud(cloud);
  if (indices) ne.setIndices(indices);
  ne.setKSearch(k_normals);
  ne.setViewPoint(viewpoint.x(), viewpoint.y(), viewpoint.z());
  ne.compute(*normals);  // one normal per index, in index order
  Cloud::Ptr local = cloud;
  if (indices) {
    local.reset(new Cloud);
    pcl::copyPointCloud(*cloud, *indices, *local);
  }
  pcl::SACSegmentationFromNormals<pcl::PointXYZ, pcl::Normal> seg;
  seg.setOptimizeCoefficients(true);
  seg.setModelType(pcl::SACMODEL_CYLINDER);
  seg.setMethodType(pcl::SAC_RANSAC);
  seg.setNormalDistanceWeight(0.1);
  seg.setMaxIterations(max_iterations);
  seg.setDistanceThreshold(threshold_mm);
  seg.setRadiusLimits(min_radius_mm, max_radius_mm);
  seg.setInputCloud(local);
  seg.setInputNormals(normals);
  pcl::PointIndices inliers;
  pcl::ModelCoefficients c;
  seg.segment(inliers, c);
  CylinderFit fit;
  if (c.values.size() != 7 || inliers.indices.empty()) return fit;
  fit.ok = true;
  fit.point = Eigen::Vector3d(c.values[0], c.values[1], c.values[2]);
  fit.axis = Eigen::Vector3d(c.values[3], c.values[4], c.values[5]).normalized();
  fit.radius_mm = c.values[6];
  for (int i : inliers.indices) fit.inliers.push_back(indices ? (*indices)[i] : i);
  return fit;
}

// ---- a cable as a chain of RANSAC cylinders: the best PCL-only approximation of ewis's trace -------------
// From the CAD sample with the most scan points within the radius: crop a sphere of 2 radii around the
// current centre, fit a cylinder (normals + SACSegmentationFromNormals, radius within 30% of the nominal),
// put the centre on the fitted axis and step one radius along it; both ways, until a fit fails, turns more
// than 35 deg or its axis misses the predicted centre by more than half a radius. No gap bridging.
struct Chain {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments;  // axis pieces, start -> end
  std::vector<double> radii_mm;
  double length_mm = 0, radius_mm = 0;
};

static double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p - a - t * ab).norm();
}
static double distance_to_chain(const Chain& c, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [a, b] : c.segments) best = std::min(best, distance_to_segment(p, a, b));
  return best;
}

static Chain trace_chain(const Cloud::Ptr& cloud, const pcl::search::KdTree<pcl::PointXYZ>::Ptr& tree,
                         const std::vector<Eigen::Vector3d>& cad, double radius_mm, const Eigen::Vector3f& viewpoint) {
  Chain chain;
  const auto point = [](const Eigen::Vector3d& p) { return pcl::PointXYZ(float(p.x()), float(p.y()), float(p.z())); };
  pcl::Indices idx;
  std::vector<float> d2;
  std::size_t best = 0, best_count = 0;
  for (std::size_t i = 0; i < cad.size(); ++i) {
    const std::size_t n = tree->radiusSearch(point(cad[i]), radius_mm, idx, d2);
    if (n > best_count) best = i, best_count = n;
  }
  if (best_count < 10) return chain;
  const auto fit_at = [&](const Eigen::Vector3d& centre) {
    pcl::IndicesPtr crop(new pcl::Indices);
    tree->radiusSearch(point(centre), 2.0 * radius_mm, *crop, d2);
    CylinderFit fit;
    if (crop->size() < 30) return fit;
    // a few hundred points: one thread (OpenMP's start-up would cost more than the work)
    fit = fit_cylinder(cloud, tree, crop, 0.7 * radius_mm, 1.3 * radius_mm, 0.5, 16, viewpoint, 1000, 1);
    if (fit.inliers.size() < 30) fit.ok = false;
    return fit;
  };
  const auto on_axis = [](const CylinderFit& f, const Eigen::Vector3d& p) {
    return Eigen::Vector3d(f.point + (p - f.point).dot(f.axis) * f.axis);
  };
  const CylinderFit first = fit_at(cad[best]);
  if (!first.ok) return chain;
  const Eigen::Vector3d start = on_axis(first, cad[best]);
  chain.radii_mm.push_back(first.radius_mm);
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> back;  // traced the other way, reversed below
  for (int side = 0; side < 2; ++side) {
    Eigen::Vector3d c = start, dir = side == 0 ? first.axis : Eigen::Vector3d(-first.axis);
    auto& out = side == 0 ? chain.segments : back;
    for (int step = 0; step < 4000; ++step) {  // at most 4000 radii each way
      const Eigen::Vector3d predicted = c + radius_mm * dir;
      const CylinderFit f = fit_at(predicted);
      if (!f.ok) break;
      const Eigen::Vector3d axis = f.axis.dot(dir) < 0 ? Eigen::Vector3d(-f.axis) : f.axis;
      const Eigen::Vector3d next = on_axis(f, predicted);
      if (axis.dot(dir) < std::cos(35.0 * M_PI / 180.0) || (next - predicted).norm() > 0.5 * radius_mm) break;
      out.emplace_back(c, next);
      chain.radii_mm.push_back(f.radius_mm);
      chain.length_mm += (next - c).norm();
      c = next;
      dir = axis;
    }
  }
  // one end to the other: the backward pieces reversed (farthest first), then the forward ones
  for (const auto& [a, b] : back) chain.segments.insert(chain.segments.begin(), {b, a});
  std::vector<double> r = chain.radii_mm;
  std::nth_element(r.begin(), r.begin() + r.size() / 2, r.end());
  chain.radius_mm = r[r.size() / 2];
  return chain;
}

static std::vector<Eigen::Vector3d> load_points(const std::string& path) { return to_double(*load(path)); }

static int chain_step(const Cloud::Ptr& cloud, const std::string& cad_file, double radius_mm,
                      const std::string& pose_file) {
  const std::vector<Eigen::Vector3d> cad = load_points(cad_file);
  const Eigen::Vector3f sensor = steps::read_matrix4(pose_file).topRightCorner<3, 1>().cast<float>();
  steps::Timer t;
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  tree->setInputCloud(cloud);
  const Chain chain = trace_chain(cloud, tree, cad, radius_mm, sensor);
  const double ms = t.ms();
  std::size_t covered = 0;
  for (const auto& p : cad) covered += distance_to_chain(chain, p) <= 2.0 * radius_mm;
  steps::print("chain", ms, chain.length_mm,
               steps::kv("radius_mm", chain.radius_mm, 3) + " sub_cables=" + std::to_string(chain.segments.size()) +
                   " " + steps::kv("cad_covered", double(covered) / cad.size(), 3));
  return 0;
}

// ---- the whole inspection, PCL only (the best approximation of `ewis inspect`; inputs from `prepare`) ------
static int inspect_step(const std::string& data_dir) {
  struct CableInput {
    std::string name, cad_file, attached_file;
    double radius_mm = 0, clearance_mm = 0;
  };
  std::map<std::string, std::string> files;
  double ror_radius_mm = 0;
  int ror_k = 0;
  std::vector<CableInput> cable_inputs;
  std::ifstream manifest(data_dir + "/inspect.txt");
  for (std::string key; manifest >> key;) {
    if (key == "ror") {
      manifest >> ror_radius_mm >> ror_k;
    } else if (key == "cable") {
      CableInput c;
      manifest >> c.name >> c.radius_mm >> c.clearance_mm >> c.cad_file >> c.attached_file;
      cable_inputs.push_back(c);
    } else {
      manifest >> files[key];
    }
  }
  if (cable_inputs.empty()) throw std::runtime_error(data_dir + "/inspect.txt: no cable");
  std::vector<std::pair<std::string, double>> times_ms;
  steps::Timer total, t;
  const auto lap = [&](const char* name) {
    times_ms.emplace_back(name, t.ms());
    t = steps::Timer{};
  };

  // load
  const Cloud::Ptr scan = load(files.at("scan"));
  const NormalCloud::Ptr rigid = load_with_normals(files.at("rigid"));
  struct CableData {
    std::vector<Eigen::Vector3d> cad;
    Cloud::Ptr attached;
  };
  std::vector<CableData> cable_data;
  for (const CableInput& c : cable_inputs) cable_data.push_back({load_points(c.cad_file), load(c.attached_file)});
  const Eigen::Matrix4d initial = steps::read_matrix4(files.at("pose"));
  lap("load");

  // radius outlier removal, ewis's derived parameters
  Cloud::Ptr filtered(new Cloud);
  pcl::RadiusOutlierRemoval<pcl::PointXYZ> ror;
  ror.setInputCloud(scan);
  ror.setRadiusSearch(ror_radius_mm);
  ror.setMinNeighborsInRadius(ror_k);
  ror.filter(*filtered);
  lap("filter");

  // ICP with normals onto the rigid CAD samples, faces turned away from the sensor (at the initial pose)
  // culled, on a 50 k strided subsample, from 3 x 60 mm (the error `ewis inspect` allows) down to 1.6 mm
  const Eigen::Vector3d eye = initial.topRightCorner<3, 1>();
  NormalCloud::Ptr facing(new NormalCloud);
  for (const auto& q : *rigid) {
    const Eigen::Vector3d to_eye = eye - Eigen::Vector3d(q.x, q.y, q.z);
    if (Eigen::Vector3d(q.normal_x, q.normal_y, q.normal_z).dot(to_eye) > -0.2 * to_eye.norm()) facing->push_back(q);
  }
  Cloud sub;
  const std::size_t n = filtered->size(), m = std::min<std::size_t>(n, 50000);
  for (std::size_t i = 0; i < m; ++i) sub.push_back((*filtered)[i * n / m]);
  int iterations = 0;
  const Eigen::Matrix4d scan_to_cad = align(sub, facing, initial, 3.0 * 60.0, iterations);
  Cloud::Ptr cloud(new Cloud);
  pcl::transformPointCloud(*filtered, *cloud, scan_to_cad.cast<float>());
  lap("register");

  // per cable: the points within max(3 radii, 15 mm) of its CAD samples and farther than 1.5 mm from the rigid
  // CAD samples, traced as a chain of cylinders; its points: those within its radius + 1 mm of the chain's axis
  pcl::KdTreeFLANN<pcl::PointNormal> rigid_tree;
  rigid_tree.setInputCloud(rigid);
  pcl::Indices idx;
  std::vector<float> d2;
  std::vector<Cloud::Ptr> crops;
  std::vector<pcl::Indices> crop_of(cable_inputs.size());  // index in `cloud`
  for (std::size_t c = 0; c < cable_inputs.size(); ++c) {
    Cloud::Ptr samples(new Cloud);
    for (const Eigen::Vector3d& p : cable_data[c].cad) samples->emplace_back(float(p.x()), float(p.y()), float(p.z()));
    pcl::KdTreeFLANN<pcl::PointXYZ> sample_tree;
    sample_tree.setInputCloud(samples);
    const float reach = float(std::max(3.0 * cable_inputs[c].radius_mm, 15.0));
    crops.emplace_back(new Cloud);
    for (std::size_t i = 0; i < cloud->size(); ++i) {
      const pcl::PointXYZ& p = (*cloud)[i];
      if (sample_tree.nearestKSearch(p, 1, idx, d2) < 1 || d2[0] > reach * reach) continue;
      pcl::PointNormal q;
      q.x = p.x, q.y = p.y, q.z = p.z;
      if (rigid_tree.nearestKSearch(q, 1, idx, d2) == 1 && d2[0] <= 1.5f * 1.5f) continue;
      crops.back()->push_back(p);
      crop_of[c].push_back(int(i));
    }
  }
  lap("crop");
  std::vector<Chain> chains;
  std::vector<char> on_cable(cloud->size(), 0);
  std::vector<pcl::Indices> cable_points(cable_inputs.size());
  const Eigen::Vector3f sensor = scan_to_cad.topRightCorner<3, 1>().cast<float>();
  for (std::size_t c = 0; c < cable_inputs.size(); ++c) {
    const double r = cable_inputs[c].radius_mm;
    pcl::search::KdTree<pcl::PointXYZ>::Ptr crop_tree(new pcl::search::KdTree<pcl::PointXYZ>);
    crop_tree->setInputCloud(crops[c]);
    chains.push_back(trace_chain(crops[c], crop_tree, cable_data[c].cad, r, sensor));
    for (std::size_t i = 0; i < crops[c]->size(); ++i) {
      const auto& p = (*crops[c])[i];
      if (!chains.back().segments.empty() && distance_to_chain(chains.back(), Eigen::Vector3d(p.x, p.y, p.z)) <= r + 1.0) {
        on_cable[crop_of[c][i]] = 1;
        cable_points[c].push_back(crop_of[c][i]);
      }
    }
  }
  lap("trace");

  // interference: points on no cable within the clearance of a cable's points (radius searches around them in
  // the whole cloud's k-d tree), not on the cable's attached elements (1.5 mm of their CAD samples), grouped by
  // EuclideanClusterExtraction (1.5 mm, at least 10 points)
  pcl::search::KdTree<pcl::PointXYZ> cloud_tree;
  cloud_tree.setInputCloud(cloud);
  std::vector<std::size_t> clusters_per_cable;
  for (std::size_t c = 0; c < cable_inputs.size(); ++c) {
    std::vector<char> near(cloud->size(), 0);
    for (int i : cable_points[c]) {
      cloud_tree.radiusSearch((*cloud)[i], cable_inputs[c].clearance_mm, idx, d2);
      for (int j : idx) near[j] = !on_cable[j];
    }
    pcl::KdTreeFLANN<pcl::PointXYZ> attached_tree;
    const bool has_attached = !cable_data[c].attached->empty();
    if (has_attached) attached_tree.setInputCloud(cable_data[c].attached);
    Cloud::Ptr candidates(new Cloud);
    for (std::size_t i = 0; i < cloud->size(); ++i) {
      if (!near[i]) continue;
      if (has_attached && attached_tree.nearestKSearch((*cloud)[i], 1, idx, d2) == 1 && d2[0] <= 1.5f * 1.5f) continue;
      candidates->push_back((*cloud)[i]);
    }
    std::vector<pcl::PointIndices> found;
    if (!candidates->empty()) {
      pcl::search::KdTree<pcl::PointXYZ>::Ptr candidate_tree(new pcl::search::KdTree<pcl::PointXYZ>);
      candidate_tree->setInputCloud(candidates);
      pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
      ec.setClusterTolerance(1.5);
      ec.setMinClusterSize(10);
      ec.setMaxClusterSize(std::numeric_limits<int>::max());
      ec.setSearchMethod(candidate_tree);
      ec.setInputCloud(candidates);
      ec.extract(found);
    }
    clusters_per_cable.push_back(found.size());
  }
  lap("interference");
  const double ms = total.ms();

  const Eigen::Matrix4d truth = steps::read_matrix4(files.at("truth"));
  const steps::PoseError e = steps::pose_error(scan_to_cad, truth, steps::centroid(to_double(*scan)));
  int found = 0;
  std::string detail = steps::kv("reg_rot_deg", e.rotation_deg, 4) + " " + steps::kv("reg_trans_mm", e.translation_mm, 3);
  for (std::size_t c = 0; c < cable_inputs.size(); ++c) {
    found += !chains[c].segments.empty();
    detail += " " + cable_inputs[c].name + ":" + steps::kv("d", 2.0 * chains[c].radius_mm, 2) + "," +
              steps::kv("L", chains[c].length_mm, 1) + ",clusters=" + std::to_string(clusters_per_cable[c]);
  }
  detail += " times_s:";
  for (const auto& [name, step_ms] : times_ms) detail += " " + steps::kv(name, step_ms / 1000.0, 2);
  steps::print("inspect", ms, found, detail);
  return 0;
}

int main(int argc, char** argv) try {
  if (argc < 3) return steps::usage(argv[0]);
  const std::string step = argv[1], file = argv[2];
  if (step == "inspect") return inspect_step(file);
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
  } else if (step == "icp" && argc >= 6) {
    return icp_step(cloud, argv[3], argv[4], argv[5]);
  } else if (step == "chain" && argc >= 6) {
    return chain_step(cloud, argv[3], std::stod(argv[4]), argv[5]);
  } else if (step == "cylinder") {
    steps::Timer t;
    pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
    tree->setInputCloud(cloud);
    // k 30 normals, 2.5 sigma of the noise, radius free up to 4x the truth
    const CylinderFit fit = fit_cylinder(cloud, tree, nullptr, 0.0, 20.0, 0.5, 30, Eigen::Vector3f::Zero(), 10000, 2);
    const double ms = t.ms();
    if (!fit.ok) throw std::runtime_error("no cylinder found");
    steps::print(step, ms, fit.radius_mm,
                 steps::cylinder_detail(fit.point, fit.axis, fit.radius_mm) + " inliers=" +
                     std::to_string(fit.inliers.size()));
  } else {
    return steps::usage(argv[0]);
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "pcl_steps: %s\n", e.what());
  return 2;
}
