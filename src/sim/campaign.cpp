// Scene folders and campaigns (CONTRACT.md "ewis simulate").
#include "ewis/sim/campaign.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "ewis/core/error.hpp"
#include "ewis/io/cloud_io.hpp"
#include "ewis/io/plan_file.hpp"
#include "ewis/io/pose_file.hpp"
#include "ewis/raycast/raycaster.hpp"
#include "ewis/sim/gap_visibility.hpp"
#include "rng.hpp"

namespace ewis::sim {

namespace fs = std::filesystem;

namespace {

void make_dir(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) throw InputError(dir, "exists and is not a directory");
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir, "cannot create directory: " + ec.message());
}

std::string join(const std::string& dir, const std::string& name) { return (fs::path(dir) / name).string(); }

struct ScanOutput {
  ScanResult scan;
  double seconds = 0;
};

ScanOutput scan_scene(const Scene& scene, const Camera& camera, const Pose& camera_to_cad, const SensorParams& p) {
  const auto t0 = std::chrono::steady_clock::now();
  const Raycaster caster(scene);
  ScanOutput out;
  out.scan = scan(caster, camera, camera_to_cad, p);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

void write_scan_files(const std::string& dir, const ScanResult& scan, const Camera& camera, const Pose& truth,
                      const SimulateOptions& o, std::uint64_t seed) {
  write_ply(scan.cloud, join(dir, "scan.ply"));
  write_pose(perturb_pose(truth, o.pose_error_deg, o.pose_error_mm, mix(seed, 0, 6)), join(dir, "pose.txt"));
  write_png(scan_image(scan.cloud, camera), join(dir, "scan.png"));
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

nlohmann::json parse_json_file(const std::string& path);  // below

}  // namespace

Pose perturb_pose(const Pose& truth, double max_deg, double max_mm, std::uint64_t seed) {
  Rng rng(seed);
  const Eigen::Vector3d axis = rng.unit_vector();
  const double angle = rng.uniform(0.0, std::max(0.0, max_deg)) * M_PI / 180.0;
  const Eigen::Vector3d shift = rng.unit_vector() * rng.uniform(0.0, std::max(0.0, max_mm));
  Pose p = truth;
  p.linear() = Eigen::AngleAxisd(angle, axis).toRotationMatrix() * truth.linear();
  p.translation() = truth.translation() + shift;
  return p;
}

SceneSummary write_scene(const std::string& dir, const SimulateOptions& o, const ProgressFn& progress) {
  make_dir(dir);
  if (progress) progress("simulate", 0.0);
  SimScene sim = generate_scene(o.scene);
  const Scene cad = nominal_scene(sim, o.mesh);
  SceneSummary s;
  s.dir = dir;
  s.seed = o.scene.seed;
  s.defect = defect_kind_name(sim.requested);
  s.defects = sim.defects.size();
  s.cables = sim.cables.size();
  s.attempts = sim.attempts;
  write_obj(cad, join(dir, "scene.obj"));
  write_file_atomic(join(dir, "plan.json"), plan_to_json(scene_plan(sim)));
  if (progress) progress("simulate", 0.3);
  const Scene built = as_built_scene(sim, o.mesh);
  s.triangles = built.triangle_count();
  if (o.scene_only) {
    write_obj(built, join(dir, "asbuilt.obj"));
    write_file_atomic(join(dir, "scene_truth.json"), truth_to_json(sim, sim.camera_to_cad, nullptr));
    if (progress) progress("simulate", 1.0);
    return s;
  }
  const Pose truth = o.camera_to_cad ? *o.camera_to_cad : sim.camera_to_cad;
  SensorParams sp = o.sensor;
  sp.seed = mix(o.scene.seed, 0, 5);
  const Camera camera = sim.sensor.camera();
  const ScanOutput scan = scan_scene(built, camera, truth, sp);
  if (progress) progress("simulate", 0.8);
  write_scan_files(dir, scan.scan, camera, truth, o, o.scene.seed);
  mark_seen_gaps(sim, built, scan.scan, truth);
  write_file_atomic(join(dir, "truth.json"), truth_to_json(sim, truth, &scan.scan, &sp));
  s.points = scan.scan.cloud.size();
  s.outliers = scan.scan.outliers;
  s.scan_seconds = scan.seconds;
  if (progress) progress("simulate", 1.0);
  return s;
}

std::uint64_t campaign_scene_seed(std::uint64_t seed, std::size_t i) { return mix(seed, i, 99); }

void campaign_scene_defect(std::size_t i, DefectKind forced, DefectKind& kind, std::string& with) {
  with.clear();
  kind = DefectKind::None;
  if (i % 2 == 0) return;
  if (forced != DefectKind::Random && forced != DefectKind::None) {
    kind = forced;
    return;
  }
  switch ((i / 2) % 5) {
    case 0: kind = DefectKind::Bend; break;
    case 1: kind = DefectKind::Clearance; with = "pipe"; break;
    case 2: kind = DefectKind::ForeignObject; break;
    case 3: kind = DefectKind::Clearance; with = "bracket"; break;
    default: kind = DefectKind::Clearance; with = "cable"; break;
  }
}

std::vector<SceneSummary> write_campaign(const std::string& dir, std::size_t count, const SimulateOptions& options,
                                         DefectKind forced, const ProgressFn& progress) {
  make_dir(dir);
  std::vector<SceneSummary> out;
  for (std::size_t i = 0; i < count; ++i) {
    SimulateOptions o = options;
    o.scene.seed = campaign_scene_seed(options.scene.seed, i);
    campaign_scene_defect(i, forced, o.scene.defect, o.scene.clearance_with);
    char name[32];
    std::snprintf(name, sizeof name, "scene_%03zu", i);
    out.push_back(write_scene(join(dir, name), o));
    if (progress) progress("campaign", double(i + 1) / double(count));
  }
  return out;
}

SceneSummary write_scan_of_cad(const std::string& dir, const std::string& cad_path, const std::string& plan_path,
                               const std::string& asbuilt_path, const std::string& scene_truth_path,
                               const Pose& camera_to_cad, const SimulateOptions& o, std::uint64_t seed) {
  const InspectionPlan plan = read_plan(plan_path);
  const Scene cad = load_scene(cad_path);
  const Scene built = asbuilt_path.empty() ? cad : load_scene(asbuilt_path);
  nlohmann::json truth;
  if (!scene_truth_path.empty()) {
    truth = parse_json_file(scene_truth_path);
    if (!truth.is_object() || !truth.contains("cables") || !truth.contains("defects"))
      throw InputError(scene_truth_path, "not a truth file (no cables/defects)");
  } else {
    truth["cables"] = nlohmann::json::array();
    truth["defects"] = nlohmann::json::array();
  }
  make_dir(dir);
  // The folder is a whole scene: copy the CAD and plan when scanning into another folder.
  std::error_code ec;
  if (!fs::equivalent(fs::path(cad_path).parent_path().empty() ? "." : fs::path(cad_path).parent_path(), dir, ec)) {
    write_obj(cad, join(dir, "scene.obj"));
    write_file_atomic(join(dir, "plan.json"), plan_to_json(plan));
  }
  SensorParams sp = o.sensor;
  sp.seed = mix(seed, 0, 5);
  const Camera camera = plan.sensor.camera();
  const ScanOutput scan = scan_scene(built, camera, camera_to_cad, sp);
  write_scan_files(dir, scan.scan, camera, camera_to_cad, o, seed);
  nlohmann::json m = nlohmann::json::array();
  for (int r = 0; r < 4; ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (int c = 0; c < 4; ++c) row.push_back(camera_to_cad.matrix()(r, c));
    m.push_back(row);
  }
  truth["camera_to_cad"] = m;
  truth["scan"] = {{"points", scan.scan.cloud.size()}, {"surface_points", scan.scan.surface_points},
                   {"outliers", scan.scan.outliers}, {"shadowed", scan.scan.shadowed}, {"grazing", scan.scan.grazing}};
  write_file_atomic(join(dir, "truth.json"), truth.dump(1) + "\n");
  SceneSummary s;
  s.dir = dir;
  s.seed = seed;
  s.defect = truth.value("requested_defect", std::string("unknown"));
  s.defects = truth["defects"].size();
  s.cables = truth["cables"].size();
  s.triangles = built.triangle_count();
  s.points = scan.scan.cloud.size();
  s.outliers = scan.scan.outliers;
  s.scan_seconds = scan.seconds;
  return s;
}

namespace {
Pose pose_from_json(const nlohmann::json& m, const std::string& path) {
  if (!m.is_array() || m.size() != 4) throw InputError(path, "camera_to_cad is not a 4x4 matrix");
  std::ostringstream text;
  text.precision(17);
  for (const auto& row : m) {
    if (!row.is_array() || row.size() != 4) throw InputError(path, "camera_to_cad is not a 4x4 matrix");
    for (const auto& v : row) {
      if (!v.is_number()) throw InputError(path, "camera_to_cad holds a non-number");
      text << v.get<double>() << ' ';
    }
  }
  return parse_pose(text.str(), path);
}

nlohmann::json parse_json_file(const std::string& path) {
  try {
    return nlohmann::json::parse(read_text(path));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, std::string("not valid JSON: ") + e.what());
  }
}
}  // namespace

Pose read_truth_pose(const std::string& path) {
  const nlohmann::json j = parse_json_file(path);
  if (!j.is_object() || !j.contains("camera_to_cad")) throw InputError(path, "no camera_to_cad");
  return pose_from_json(j["camera_to_cad"], path);
}

Pose read_viewpoint_pose(const std::string& path, int rank) {
  const nlohmann::json j = parse_json_file(path);
  if (!j.is_object() || !j.contains("best") || !j["best"].is_array()) throw InputError(path, "no 'best' list of viewpoints");
  for (const auto& b : j["best"]) {
    if (!b.is_object() || !b.contains("rank") || !b["rank"].is_number() || b["rank"].get<double>() != rank) continue;
    if (!b.contains("camera_to_cad")) throw InputError(path, "rank " + std::to_string(rank) + ": no camera_to_cad");
    return pose_from_json(b["camera_to_cad"], path);
  }
  throw InputError(path, "no viewpoint of rank " + std::to_string(rank));
}

}  // namespace ewis::sim
