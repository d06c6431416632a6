// ewis register: registers point cloud or mesh S onto T (CONTRACT.md "ewis register"). Cloud onto mesh uses the
// scan-to-CAD registration (point-to-plane onto triangle-normal samples); cloud onto cloud estimates target
// normals; a mesh source is sampled into a cloud. Without --pose the registration is global.
#include <chrono>
#include <cmath>
#include <iostream>
#include <optional>

#include "common.hpp"
#include "ewis/core/error.hpp"
#include "ewis/filter/resolution.hpp"
#include "ewis/io/pose_file.hpp"
#include "ewis/register/cloud_registration.hpp"
#include "ewis/register/registration_input.hpp"
#include "ewis/register/scan_to_cad.hpp"
#include "ewis/sample/mesh_sampling.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis::cli {
namespace {

Cloud sample_source_mesh(const Scene& scene) {
  MeshSamplingParams sp;
  sp.spacing_mm = 1.0;
  sp.max_points = 500000;
  return sample_mesh(scene, sp).cloud;
}

}  // namespace

Command add_register(CLI::App& root, CommonOptions& common) {
  struct Options {
    std::string source, target, pose, out;
    std::string units = "mm";
    bool no_visibility = false;
    double min_fitness = -1.0;
    std::uint64_t seed = 1;
  };
  auto opt = std::make_shared<Options>();
  Command cmd;
  cmd.app = root.add_subcommand("register", "Register a point cloud or mesh S onto T; writes the 4x4 S-to-T matrix");
  cmd.app->add_option("--source", opt->source, "Source S: point cloud (PLY, PCD, XYZ) or mesh (OBJ, STL, PLY with faces, glTF...)")
      ->required();
  cmd.app->add_option("--target", opt->target, "Target T: point cloud or mesh (a mesh: the CAD, in mm)")->required();
  cmd.app->add_option("--pose", opt->pose, "Initial S-to-T pose (16 numbers, row-major 4x4); without it: global registration");
  cmd.app->add_option("--out", opt->out, "Output: the 4x4 row-major matrix mapping S into T's frame")->required();
  cmd.app->add_option("--scan-units", opt->units, "Units of point-cloud inputs: mm, m or in (meshes are mm)")
      ->check(CLI::IsMember({"mm", "m", "in"}));
  cmd.app->add_flag("--no-visibility", opt->no_visibility,
                    "Cloud onto mesh: do not assume S is in its sensor's frame (no culling of CAD faces turned away)");
  cmd.app->add_option("--min-fitness", opt->min_fitness, "Least fitness for success (default 0.3 onto a mesh, 0.25 onto a cloud)")
      ->check(CLI::Range(0.0, 1.0));
  cmd.app->add_option("--seed", opt->seed, "Seed of the global registration (RANSAC)");
  add_common_options(cmd.app, common);
  cmd.run = [opt, &common]() -> int {
    const auto t0 = std::chrono::steady_clock::now();
    const LengthUnit unit = parse_length_unit(opt->units);
    std::optional<Pose> initial;
    if (!opt->pose.empty()) initial = read_pose(opt->pose);
    RegistrationInput src = read_registration_input(opt->source, unit);
    const RegistrationInput tgt = read_registration_input(opt->target, unit);
    const bool source_is_scan = !src.is_mesh;
    if (src.is_mesh) src.cloud = sample_source_mesh(src.scene);
    if (src.cloud.size() < 3) throw InputError(opt->source, "no points to register");
    log(common, opt->source + ": " + std::to_string(src.cloud.size()) + " points" + (src.is_mesh ? " (sampled mesh)" : ""));
    const ProgressFn progress = make_progress(common);

    RegistrationResult reg;
    bool valid = false, used_global = false;
    std::string why = "is below the least accepted (the clouds may not overlap, or the initial pose is too far off)";
    if (tgt.is_mesh) {
      const KdTree tree(src.cloud.points);
      const double res_mm = spatial_resolution(tree, 20000).mean_mm;
      CadTargetParams tp;
      tp.spacing_mm = std::clamp(res_mm, 1.0, 5.0);  // ~ the scan resolution, at least 1 mm (paper 4.1.1)
      tp.exact_surface = true;  // the last step on the exact surface (surface_refine.hpp); tgt outlives the target
      const CadTarget target = build_cad_target(tgt.scene, InspectionPlan{}, tp);
      ScanToCadParams sp;
      sp.icp.use_source_viewpoint = source_is_scan && !opt->no_visibility;
      sp.icp.noise_mm = std::max(0.2, 0.3 * res_mm);
      sp.global.seed = opt->seed;
      if (opt->min_fitness >= 0) sp.min_fitness = opt->min_fitness;
      const ScanToCadResult r = register_scan_to_cad(src.cloud, target, initial, sp, progress);
      reg = r.registration;
      valid = r.valid;
      used_global = r.used_global;
      if (r.registration.fitness >= sp.min_fitness && r.free_space.fraction() > sp.max_in_front_fraction)
        why = "is enough, but the pose puts " + std::to_string(std::lround(100.0 * r.free_space.fraction())) +
              " % of the target's faces toward the sensor in front of what the source measured";
    } else {
      CloudRegistrationParams cp;
      cp.global.seed = opt->seed;
      if (opt->min_fitness >= 0) cp.min_fitness = opt->min_fitness;
      const CloudRegistrationResult r = register_clouds(src.cloud, tgt.cloud, initial, cp, progress);
      reg = r.registration;
      valid = r.valid;
      used_global = r.used_global;
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    nlohmann::json line = {{"rmse_mm", reg.rmse_mm},
                           {"fitness", reg.fitness},
                           {"converged", reg.converged},
                           {"iterations", reg.iterations},
                           {"inliers", reg.inliers},
                           {"inlier_distance_mm", reg.inlier_distance_mm},
                           {"global", used_global},
                           {"seconds", seconds}};
    if (!valid) {
      std::cout << line.dump() << std::endl;
      throw ProcessingError("registration failed: fitness " + std::to_string(reg.fitness) + " " + why);
    }
    write_pose(reg.source_to_target, opt->out);
    std::cout << line.dump() << std::endl;
    return 0;
  };
  return cmd;
}

}  // namespace ewis::cli
