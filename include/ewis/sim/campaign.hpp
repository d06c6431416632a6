#pragma once
// Writing simulated scenes to folders (CONTRACT.md "ewis simulate"): scene.obj (nominal CAD), plan.json,
// scan.ply (sensor frame), pose.txt (the true pose perturbed as a robot's estimate), truth.json, scan.png.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ewis/core/progress.hpp"
#include "ewis/io/image_io.hpp"
#include "ewis/sim/scene_generator.hpp"
#include "ewis/sim/sensor.hpp"

namespace ewis::sim {

struct SimulateOptions {
  SceneParams scene;
  SensorParams sensor;                 // its seed is derived from the scene seed
  double pose_error_deg = 5.0;         // pose.txt: rotation of up to this about a random axis
  double pose_error_mm = 30.0;         // and a translation of up to this
  TubeMeshParams mesh;
  std::optional<Pose> camera_to_cad;   // scan from this pose instead of the generated one (viewpoints.json)
  bool scene_only = false;             // write scene.obj, plan.json, asbuilt.obj, scene_truth.json only
};

struct SceneSummary {
  std::string dir;
  std::uint64_t seed = 0;
  std::string defect;                  // requested kind ("none", "bend", ...)
  std::size_t defects = 0, cables = 0, triangles = 0;
  std::size_t points = 0, outliers = 0;
  double scan_seconds = 0.0;
  int attempts = 0;
};

// The true pose perturbed by a rotation of up to max_deg (random axis) and a translation of up to max_mm.
Pose perturb_pose(const Pose& truth, double max_deg, double max_mm, std::uint64_t seed);

// Depth-shaded picture of a sensor-frame cloud splatted into the camera image (nearest point per pixel).
Image scan_image(const Cloud& cloud_in_sensor_frame, const Camera& camera);

// truth.json text (schema truth.schema.json plus extra fields); `scan` adds scan statistics when given.
std::string truth_to_json(const SimScene& sim, const Pose& camera_to_cad, const ScanResult* scan,
                          const SensorParams* sensor = nullptr);

// One scene into `dir` (created). Throws InputError when the folder cannot be written.
SceneSummary write_scene(const std::string& dir, const SimulateOptions& options, const ProgressFn& progress = {});

// Seed of scene i of a campaign.
std::uint64_t campaign_scene_seed(std::uint64_t seed, std::size_t i);
// Defect kind of scene i: odd scenes have defects, cycling bend, clearance (pipe), foreign object,
// clearance (bracket), clearance (cable); `forced` replaces the cycle when not Random/None.
void campaign_scene_defect(std::size_t i, DefectKind forced, DefectKind& kind, std::string& clearance_with);
// N scenes in dir/scene_000, dir/scene_001, ...
std::vector<SceneSummary> write_campaign(const std::string& dir, std::size_t count, const SimulateOptions& options,
                                         DefectKind forced = DefectKind::Random, const ProgressFn& progress = {});

// Scans an existing CAD (`cad_path`, with plan) into `dir`: the as-built geometry is `asbuilt_path` when
// given (else the CAD itself) and the truth's cables/defects come from `scene_truth_path` when given.
SceneSummary write_scan_of_cad(const std::string& dir, const std::string& cad_path, const std::string& plan_path,
                               const std::string& asbuilt_path, const std::string& scene_truth_path,
                               const Pose& camera_to_cad, const SimulateOptions& options, std::uint64_t seed);

// The camera pose of rank K in a viewpoints.json written by `ewis plan` (InputError when absent).
Pose read_viewpoint_pose(const std::string& viewpoints_path, int rank);
// The camera_to_cad of a truth.json / scene_truth.json (InputError when absent or malformed).
Pose read_truth_pose(const std::string& truth_path);

}  // namespace ewis::sim
