// The steps of bench/compare.sh through Open3D 0.16, each with its nearest Open3D equivalent and the same parameters.
#include <open3d/Open3D.h>
#include <open3d/t/geometry/RaycastingScene.h>

#include <string>

#include "steps_common.hpp"

using open3d::geometry::PointCloud;

static std::shared_ptr<PointCloud> load(const std::string& path) {
  auto cloud = std::make_shared<PointCloud>();
  if (!open3d::io::ReadPointCloud(path, *cloud)) throw std::runtime_error("cannot read " + path);
  return cloud;
}

// Point-to-plane ICP (Gauss-Newton, Cauchy kernel of ewis's scale) over the shared distance schedule.
static int icp_step(const PointCloud& source, const std::string& target_file, const std::string& init_file,
                    const std::string& truth_file) {
  using namespace open3d::pipelines::registration;
  const auto target = load(target_file);  // with the CAD's triangle normals
  if (!target->HasNormals()) throw std::runtime_error(target_file + " has no normals");
  const Eigen::Matrix4d init = steps::read_matrix4(init_file), truth = steps::read_matrix4(truth_file);
  steps::Timer t;
  Eigen::Matrix4d pose = init;
  for (double d : steps::icp_schedule_mm()) {  // RegistrationICP builds its target k-d tree at every call
    const double scale = std::max(3.0 * steps::kIcpNoiseMm, d / 3.0);
    const TransformationEstimationPointToPlane estimation(std::make_shared<CauchyLoss>(scale));
    pose = RegistrationICP(source, *target, d, pose, estimation,
                           ICPConvergenceCriteria(1e-6, 1e-6, steps::kIcpIterationsPerStage))
               .transformation_;
  }
  const double ms = t.ms();
  open3d::geometry::KDTreeFlann tree(*target);
  std::vector<int> idx;
  std::vector<double> d2;
  const steps::IcpFit fit = steps::icp_fit(source.points_, pose, [&](const Eigen::Vector3d& p, Eigen::Vector3d& q,
                                                                     Eigen::Vector3d& n) {
    if (tree.SearchKNN(p, 1, idx, d2) < 1) return false;
    q = target->points_[idx[0]];
    n = target->normals_[idx[0]];
    return true;
  });
  steps::print("icp", ms, fit.rmse_mm, steps::icp_detail(pose, truth, source.points_, fit, -1));
  return 0;
}

// One ray per pixel centre of the shared pinhole camera, cast with RaycastingScene (Embree 3 inside); the
// scene (BVH) and the rays are built inside the timer, as ewis's Raycaster and render().
static int raycast_step(const std::string& mesh_file, const std::string& pose_file) {
  using open3d::core::Tensor;
  open3d::geometry::TriangleMesh legacy;
  if (!open3d::io::ReadTriangleMesh(mesh_file, legacy)) throw std::runtime_error("cannot read " + mesh_file);
  // the tensors RaycastingScene wants (Float32 vertices, UInt32 triangles)
  std::vector<float> vertices;
  for (const auto& v : legacy.vertices_) vertices.insert(vertices.end(), {float(v.x()), float(v.y()), float(v.z())});
  std::vector<uint32_t> triangles;
  for (const auto& f : legacy.triangles_) triangles.insert(triangles.end(), {uint32_t(f[0]), uint32_t(f[1]), uint32_t(f[2])});
  const Tensor vertex_tensor(vertices, {int64_t(legacy.vertices_.size()), 3}, open3d::core::Float32);
  const Tensor triangle_tensor(triangles, {int64_t(legacy.triangles_.size()), 3}, open3d::core::UInt32);
  const Eigen::Matrix4d camera_to_cad = steps::read_matrix4(pose_file);
  const Eigen::Matrix3d R = camera_to_cad.topLeftCorner<3, 3>();
  const Eigen::Vector3d o = camera_to_cad.topRightCorner<3, 1>();
  steps::Timer t;
  open3d::t::geometry::RaycastingScene scene;
  scene.AddTriangles(vertex_tensor, triangle_tensor);
  Tensor rays = Tensor::Empty({steps::kImageHeightPx, steps::kImageWidthPx, 6}, open3d::core::Float32);
  float* r = rays.GetDataPtr<float>();
  for (int row = 0; row < steps::kImageHeightPx; ++row)
    for (int col = 0; col < steps::kImageWidthPx; ++col, r += 6) {
      const Eigen::Vector3d d = R * steps::pixel_direction_camera(col, row);
      r[0] = float(o.x()), r[1] = float(o.y()), r[2] = float(o.z());
      r[3] = float(d.x()), r[4] = float(d.y()), r[5] = float(d.z());
    }
  const auto result = scene.CastRays(rays);
  const double ms = t.ms();
  const Tensor& t_hit = result.at("t_hit");
  const float* th = t_hit.GetDataPtr<float>();
  std::size_t hits = 0;
  double sum_mm = 0;
  for (int64_t i = 0; i < t_hit.NumElements(); ++i)
    if (std::isfinite(th[i])) ++hits, sum_mm += th[i];
  // Debian 12's Embree is built with ray masks and Open3D 0.16 casts with mask 0: every ray is masked out
  const std::string invalid = hits ? "" : "invalid (no hit: Embree ray masks) ";
  steps::print("raycast", ms, double(hits), invalid + steps::kv("mean_depth_mm", hits ? sum_mm / hits : 0.0, 3));
  return 0;
}

int main(int argc, char** argv) try {
  open3d::utility::SetVerbosityLevel(open3d::utility::VerbosityLevel::Error);
  if (argc < 3) return steps::usage(argv[0]);
  const std::string step = argv[1], file = argv[2];
  if (step == "read") {
    steps::Timer t;
    auto cloud = load(file);
    steps::print(step, t.ms(), double(cloud->points_.size()));
    return 0;
  }
  if (step == "raycast" && argc >= 4) return raycast_step(file, argv[3]);
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
  } else if (step == "icp" && argc >= 6) {
    return icp_step(*cloud, argv[3], argv[4], argv[5]);
  } else {
    return steps::usage(argv[0]);
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "open3d_steps: %s\n", e.what());
  return 2;
}
