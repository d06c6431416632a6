// The steps of bench/compare.sh through ewis, timed the same way as pcl_steps and open3d_steps (input loading is
// outside the timer except for the read steps and the whole inspection; k-d tree and BVH builds are inside, as
// for the peers). Also the helper steps that write the shared inputs once (convert-pcd, prepare).
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "ewis/core/error.hpp"
#include "ewis/filter/euclidean_clusters.hpp"
#include "ewis/filter/outlier_removal.hpp"
#include "ewis/filter/resolution.hpp"
#include "ewis/filter/voxel_grid.hpp"
#include "ewis/scene/surface_index.hpp"
#include "ewis/io/cloud_io.hpp"
#include "ewis/io/plan_file.hpp"
#include "ewis/io/pose_file.hpp"
#include "ewis/raycast/raycaster.hpp"
#include "ewis/register/cad_target.hpp"
#include "ewis/register/icp.hpp"
#include "ewis/report/run_inspection.hpp"
#include "ewis/sample/mesh_sampling.hpp"
#include "ewis/scene/scene.hpp"
#include "ewis/search/kdtree.hpp"
#include "ewis/tubes/trace.hpp"
#include "steps_common.hpp"

using namespace ewis;

namespace {

std::vector<Eigen::Vector3d> to_double(const std::vector<Eigen::Vector3f>& points) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(points.size());
  for (const auto& p : points) out.push_back(p.cast<double>());
  return out;
}

Cloud cloud_of(const std::vector<Eigen::Vector3d>& points) {
  Cloud c;
  for (const auto& p : points) c.points.push_back(p.cast<float>());
  return c;
}

// Fraction of `samples` within max_mm of the chain's axis (its sub-cables, bridged ones included).
double covered_fraction(const TubeTrace& t, const std::vector<Eigen::Vector3d>& samples, double max_mm) {
  std::size_t n = 0;
  for (const auto& p : samples) n += distance_to_chain(t, p) <= max_mm;
  return samples.empty() ? 0.0 : double(n) / samples.size();
}

// The straight tube of steps::kTube as a sensor would see it: points on the side facing the origin, Gaussian
// noise along the ray, then uniform outliers in the bounding box, shuffled (a scan interleaves them).
Cloud simulate_straight_tube() {
  const steps::StraightTube& k = steps::kTube;
  std::mt19937_64 rng(k.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, k.noise_mm);
  const Eigen::Vector3d u = k.axis.unitOrthogonal(), v = k.axis.cross(u);
  std::vector<Eigen::Vector3d> pts;
  while (int(pts.size()) < k.surface_points) {
    const double s = (unit(rng) - 0.5) * k.length_mm, a = unit(rng) * 2.0 * M_PI;
    const Eigen::Vector3d n = std::cos(a) * u + std::sin(a) * v;
    const Eigen::Vector3d p = k.center_mm + s * k.axis + k.radius_mm * n;
    if (n.dot(-p) <= 0) continue;  // faces away from the sensor at the origin
    pts.push_back(p + noise(rng) * p.normalized());
  }
  Eigen::Vector3d lo = pts[0], hi = pts[0];
  for (const auto& p : pts) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const int outliers = int(std::lround(k.surface_points * k.outlier_fraction / (1.0 - k.outlier_fraction)));
  for (int i = 0; i < outliers; ++i)
    pts.push_back(lo + Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).cwiseProduct(hi - lo));
  std::shuffle(pts.begin(), pts.end(), rng);
  return cloud_of(pts);
}

// Writes the shared inputs of the ICP, cylinder, chain and inspection rows into out_dir (see RESULTS.md notes).
void prepare(const std::string& scene_dir_arg, const std::string& filtered_ply, const std::string& out_dir_arg) {
  const std::string scene_dir = std::filesystem::absolute(scene_dir_arg), out_dir = std::filesystem::absolute(out_dir_arg);
  const nlohmann::json truth = nlohmann::json::parse(std::ifstream(scene_dir + "/truth.json"));
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = truth["camera_to_cad"][r][c].get<double>();
  const Pose scan_to_cad(m);
  write_pose(scan_to_cad, out_dir + "/truth_pose.txt");

  // ICP: rigid CAD samples with triangle normals (ewis's registration target, 1 mm) and a 50 k strided
  // subsample of the filtered scan without the points on the cables (ewis's exclusion zone, at the truth)
  const Scene scene = load_scene(scene_dir + "/scene.obj");
  const InspectionPlan plan = read_plan(scene_dir + "/plan.json");
  CadTargetParams tp;
  tp.spacing_mm = 1.0;
  const CadTarget target = build_cad_target(scene, plan, tp);
  const Cloud filtered = read_cloud(filtered_ply).cloud;
  const std::vector<Eigen::Vector3f> sub = pick(filtered.points, evenly_strided(filtered.size(), 50000));
  Cloud source;
  source.points = pick(sub, points_away_from_cables(sub, scan_to_cad, target, 0.0));
  write_ply(source, out_dir + "/icp_source.ply");
  // initial pose: 3 deg about a horizontal-ish axis through the data's centre, then 15 mm off
  const Eigen::Vector3d c = scan_to_cad * steps::centroid(to_double(source.points));
  const Pose init = Eigen::Translation3d(c) *
                    make_pose(Eigen::Vector3d(1, 1, 0), 3.0, Eigen::Vector3d(2, -2, 1).normalized() * 15.0) *
                    Eigen::Translation3d(-c) * scan_to_cad;
  write_pose(init, out_dir + "/icp_init.txt");
  // the target as ewis's registration sees it from the initial pose: samples whose normal faces more than
  // ~100 deg away from the sensor are culled (else a plate's scanned top locks onto the CAD's bottom face)
  const Eigen::Vector3d eye = init.translation();
  std::vector<std::uint32_t> facing;
  for (std::uint32_t i = 0; i < target.rigid.size(); ++i) {
    const Eigen::Vector3d to_eye = eye - target.rigid.points[i].cast<double>();
    if (target.rigid.normals[i].cast<double>().dot(to_eye) > -0.2 * to_eye.norm()) facing.push_back(i);
  }
  write_ply(select(target.rigid, facing), out_dir + "/icp_target.ply");

  write_ply(simulate_straight_tube(), out_dir + "/tube.ply");

  // Chain: the filtered scan in CAD coordinates (at the truth) without the points within 1.5 mm of a rigid CAD
  // surface: the candidate cable points `ewis inspect` traces on
  std::vector<int> rigid;
  for (int e = 0; e < int(scene.elements.size()); ++e) {
    const PlanElement* pe = plan.find(scene.elements[e].name);
    if (!pe || pe->kind != ElementKind::Cable) rigid.push_back(e);
  }
  const SurfaceIndex rigid_surfaces(scene, rigid);
  Cloud chain_scan;
  for (const Eigen::Vector3f& p : filtered.points) {
    const Eigen::Vector3d q = scan_to_cad * p.cast<double>();
    if (!rigid_surfaces.closest(q, 1.5).found()) chain_scan.points.push_back(q.cast<float>());
  }
  write_ply(chain_scan, out_dir + "/chain_scan.ply");

  // Chain and inspection: per cable its CAD samples (the spacing `ewis inspect` seeds its trace with) and the
  // samples of its attached elements, CAD frame. A manifest for pcl_steps' inspection (no JSON parser there).
  std::ostringstream manifest;
  manifest << "scan " << scene_dir << "/scan.ply\npose " << scene_dir << "/pose.txt\ntruth " << out_dir
           << "/truth_pose.txt\nrigid " << out_dir << "/icp_target.ply\n";
  const RadiusOutlierResult ror = remove_radius_outliers(KdTree(read_cloud(scene_dir + "/scan.ply").cloud.points), {});
  manifest << "ror " << ror.radius_mm << " " << ror.min_neighbors << "\n";
  for (const PlanElement& e : plan.elements) {
    if (e.kind != ElementKind::Cable) continue;
    const double radius = 0.5 * e.diameter_mm;
    MeshSamplingParams sp;
    sp.spacing_mm = std::max(0.5, radius / 2);
    sp.elements = {scene.find(e.name)};
    const Cloud cable = sample_mesh(scene, sp).cloud;
    Cloud cable_points;
    cable_points.points = cable.points;
    write_ply(cable_points, out_dir + "/cad_" + e.name + ".ply");
    MeshSamplingParams ap;
    ap.spacing_mm = 1.0;
    for (const std::string& a : e.attached) ap.elements.push_back(scene.find(a));
    Cloud attached;
    if (!ap.elements.empty()) attached.points = sample_mesh(scene, ap).cloud.points;
    write_ply(attached, out_dir + "/attached_" + e.name + ".ply");
    manifest << "cable " << e.name << " " << radius << " " << e.clearance_mm << " " << out_dir << "/cad_" << e.name
             << ".ply " << out_dir << "/attached_" << e.name << ".ply\n";
  }
  write_file_atomic(out_dir + "/inspect.txt", manifest.str());
}

// The whole inspection as `ewis inspect` runs it (read, inspect, write report.json, report.html, PLY files).
int inspect_step(const std::string& data_dir) {
  const std::string scene = data_dir + "/scene", out = data_dir + "/inspect_ewis";
  std::filesystem::create_directories(out);
  InspectionInputs in;
  in.cad = scene + "/scene.obj";
  in.plan = scene + "/plan.json";
  in.scan = scene + "/scan.ply";
  in.pose = scene + "/pose.txt";
  steps::Timer t;
  const InspectionRun run = run_inspection(in, out);
  const double ms = t.ms();
  const InspectionResult& r = run.result;
  const Eigen::Matrix4d truth = steps::read_matrix4(data_dir + "/truth_pose.txt");
  const steps::PoseError e =
      steps::pose_error(r.scan_to_cad.matrix(), truth, steps::centroid(to_double(read_cloud(in.scan).cloud.points)));
  std::string detail = std::string(r.pass ? "pass" : "fail") + " " + steps::kv("reg_rot_deg", e.rotation_deg, 4) +
                       " " + steps::kv("reg_trans_mm", e.translation_mm, 3);
  int found = 0;
  for (const CableInspection& c : r.cables) {
    found += c.found;
    detail += " " + c.name + ":" + steps::kv("d", c.diameter_mm, 2) + "," + steps::kv("L", c.length_mm, 1) +
              ",interferences=" + std::to_string(c.interferences.size());
  }
  detail += " times_s: " + steps::kv("load", run.load_seconds, 2);
  for (const StepTiming& s : r.timings) detail += " " + steps::kv(s.step, s.seconds, 2);
  detail += " " + steps::kv("write", run.write_seconds, 2);
  steps::print("inspect", ms, found, detail);
  return 0;
}

}  // namespace

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
  if (step == "prepare" && argc >= 5) {  // helper for compare.sh: the shared inputs of the later rows
    prepare(file, argv[3], argv[4]);
    return 0;
  }
  if (step == "inspect") return inspect_step(file);
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
  if (step == "raycast" && argc >= 4) {
    const Scene scene = load_scene(file);
    const Pose camera_to_cad = read_pose(argv[3]);
    steps::Timer t;
    const Raycaster caster(scene);  // BVH build inside the timer, as for Open3D
    const Render image = render(caster, Camera{steps::kImageWidthPx, steps::kImageHeightPx, steps::kImageHfovDeg},
                                camera_to_cad);
    const double ms = t.ms();
    std::size_t hits = 0;
    double sum_mm = 0;
    for (float d : image.distance_mm)
      if (std::isfinite(d)) ++hits, sum_mm += d;
    steps::print(step, ms, double(hits), steps::kv("mean_depth_mm", hits ? sum_mm / hits : 0.0, 3));
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
  } else if (step == "icp" && argc >= 6) {
    const Cloud target = read_cloud(argv[3]).cloud;
    const Pose init = read_pose(argv[4]);
    const Eigen::Matrix4d truth = steps::read_matrix4(argv[5]);
    steps::Timer t;
    const KdTree tree(target.points);
    IcpParams p;  // ewis's point-to-plane ICP: LM, Cauchy kernel, the shared distance schedule
    p.initial_max_distance_mm = steps::kIcpFirstDistanceMm;
    p.final_max_distance_mm = steps::kIcpFinalDistanceMm;
    p.distance_shrink = 0.5;
    p.max_iterations_per_stage = steps::kIcpIterationsPerStage;
    p.noise_mm = steps::kIcpNoiseMm;
    const RegistrationResult r = align_point_to_plane(f.cloud.points, target, tree, init, p);
    const double ms = t.ms();
    const std::vector<Eigen::Vector3d> source = to_double(f.cloud.points);
    const Eigen::Matrix4d pose = r.source_to_target.matrix();
    const steps::IcpFit fit = steps::icp_fit(source, pose, [&](const Eigen::Vector3d& p, Eigen::Vector3d& q,
                                                                Eigen::Vector3d& n) {
      const Neighbor nb = tree.nearest(p.cast<float>());
      if (nb.index == UINT32_MAX) return false;
      q = target.points[nb.index].cast<double>();
      n = target.normals[nb.index].cast<double>();
      return true;
    });
    steps::print(step, ms, fit.rmse_mm, steps::icp_detail(pose, truth, source, fit, r.iterations));
  } else if (step == "cylinder") {
    // as `ewis tubes --seed`: radius outlier removal (parameters from the resolution), then the chain of
    // cylinders from a seed on the surface the sensor sees, at the tube's middle
    const steps::StraightTube& k = steps::kTube;
    const Eigen::Vector3d to_sensor = -k.center_mm;
    const Eigen::Vector3d seed =
        k.center_mm + k.radius_mm * (to_sensor - to_sensor.dot(k.axis) * k.axis).normalized();
    steps::Timer t;
    const KdTree raw_tree(f.cloud.points);
    const Cloud cloud = select(f.cloud, remove_radius_outliers(raw_tree, {}).kept);
    const KdTree tree(cloud.points);
    const TubeTrace trace = trace_tube(cloud, tree, seed, {});
    const double ms = t.ms();
    if (!trace.found) throw ProcessingError("no tube found at the seed");
    Eigen::Vector3d point, axis;
    steps::fit_line(trace.centerline, point, axis);
    steps::print(step, ms, trace.radius_mm,
                 steps::cylinder_detail(point, axis, trace.radius_mm) + " " + steps::kv("length_mm", trace.length_mm, 1));
  } else if (step == "chain" && argc >= 6) {
    const std::vector<Eigen::Vector3d> cad = to_double(read_cloud(argv[3]).cloud.points);
    const double radius_mm = std::stod(argv[4]);
    const Pose scan_to_cad = read_pose(argv[5]);
    steps::Timer t;
    const KdTree tree(f.cloud.points);
    TubeParams tp;  // as `ewis inspect` traces a cable (CAD frame; without its stops at attached elements)
    tp.radius_mm = radius_mm;
    tp.resolution_mm = spatial_resolution(tree, 200000).median_mm;
    tp.has_sensor = true;
    tp.sensor_position = scan_to_cad.translation();
    const TubeTrace trace = trace_cable(f.cloud, tree, cad, radius_mm, tp);
    const double ms = t.ms();
    steps::print(step, ms, trace.length_mm,
                 steps::kv("radius_mm", trace.radius_mm, 3) + " sub_cables=" + std::to_string(trace.segments.size()) +
                     " " + steps::kv("cad_covered", covered_fraction(trace, cad, 2.0 * radius_mm), 3));
  } else {
    return steps::usage(argv[0]);
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "ewis_steps: %s\n", e.what());
  return 2;
}
