// ewis simulate: the virtual scanner and synthetic inspection scenes with ground truth (CONTRACT.md,
// docs/sim.md). One scene into --out, or --campaign N scenes into --out/scene_000 ...
#include <filesystem>
#include <sstream>
#include <vector>

#include "common.hpp"
#include "ewis/core/error.hpp"
#include "ewis/sim/campaign.hpp"

namespace ewis::cli {

namespace {

std::string summary_line(const sim::SceneSummary& s) {
  std::ostringstream o;
  o.precision(3);
  o << s.dir << ": seed " << s.seed << ", defect " << s.defect << " (" << s.defects << " in truth), " << s.cables
    << " cables, " << s.triangles << " triangles";
  if (s.points > 0) o << ", " << s.points << " points (" << s.outliers << " outliers), scan " << s.scan_seconds << " s";
  return o.str();
}

}  // namespace

Command add_simulate(CLI::App& root, CommonOptions& common) {
  struct Options {
    std::string out;
    std::uint64_t seed = 1;
    int campaign = 0;
    std::string defect;
    std::string clearance_with;
    double noise_mm = 0.2;
    double outliers = 0.4;
    int mismatch_patches = 0;
    double pose_error_deg = 5.0;
    double pose_error_mm = 30.0;
    int cables = 0;
    std::vector<double> cable_diameter_mm;
    bool noise_free = false;
    std::string viewpoints;
    int rank = 1;
    bool scene_only = false;
    std::string cad, plan, asbuilt, scene_truth;
  };
  auto opt = std::make_shared<Options>();
  Command cmd;
  cmd.app = root.add_subcommand("simulate", "Generate synthetic EWIS scenes and virtual structured-light scans with ground truth");
  auto* app = cmd.app;
  app->add_option("--out", opt->out, "Output folder (one scene, or the campaign's parent folder)")->required();
  app->add_option("--seed", opt->seed, "Random seed; the same seed gives the same files");
  app->add_option("--campaign", opt->campaign, "Write N scenes in DIR/scene_000 ... (half with defects)");
  app->add_option("--defect", opt->defect, "Defect to inject: none, bend, clearance, foreign_object, random "
                                           "(default: none; a campaign mixes kinds)")
      ->check(CLI::IsMember({"none", "bend", "clearance", "foreign_object", "random"}));
  app->add_option("--clearance-with", opt->clearance_with, "For --defect clearance: pipe, bracket or cable")
      ->check(CLI::IsMember({"pipe", "bracket", "cable"}));
  app->add_option("--noise-mm", opt->noise_mm, "Noise sigma along the ray at 600 mm (grows with range^2)");
  app->add_option("--outliers", opt->outliers, "Outlier fraction of the output cloud (0-0.95)");
  app->add_option("--mismatch-patches", opt->mismatch_patches,
                  "Stereo-mismatch patches: N square patches of 2-6 px whose depths are off by 1-10 mm (default 0)");
  app->add_option("--pose-error-deg", opt->pose_error_deg, "pose.txt: rotation error of up to this (deg)");
  app->add_option("--pose-error-mm", opt->pose_error_mm, "pose.txt: translation error of up to this (mm)");
  app->add_option("--cables", opt->cables, "Number of cables, 1-3 (default: random)");
  app->add_option("--cable-diameter-mm", opt->cable_diameter_mm,
                  "LO HI: every cable's diameter drawn from [LO, HI] mm (e.g. 1.5 3: single wires; default: 3-30)")
      ->expected(2);
  app->add_flag("--noise-free", opt->noise_free, "No noise and no outliers");
  app->add_option("--viewpoints", opt->viewpoints, "viewpoints.json of `ewis plan`: scan from its camera_to_cad");
  app->add_option("--rank", opt->rank, "Rank of the viewpoint to use (default 1)");
  app->add_flag("--scene-only", opt->scene_only,
                "Write scene.obj, plan.json, asbuilt.obj and scene_truth.json only (no scan), e.g. for `ewis plan`");
  app->add_option("--cad", opt->cad, "Scan this CAD scene instead of generating one (needs --plan)");
  app->add_option("--plan", opt->plan, "Plan of --cad");
  app->add_option("--asbuilt", opt->asbuilt, "As-built geometry to scan (default: asbuilt.obj beside --cad if present)");
  app->add_option("--scene-truth", opt->scene_truth, "Truth of --cad (default: scene_truth.json beside it if present)");
  add_common_options(app, common);

  cmd.run = [opt, &common]() -> int {
    namespace fs = std::filesystem;
    const Options& o = *opt;
    if (o.noise_mm < 0) throw InputError("", "--noise-mm must be >= 0");
    if (o.outliers < 0 || o.outliers > 0.95) throw InputError("", "--outliers must be in [0, 0.95]");
    if (o.mismatch_patches < 0 || o.mismatch_patches > 1000000)
      throw InputError("", "--mismatch-patches must be in [0, 1000000]");
    if (o.pose_error_deg < 0 || o.pose_error_deg > 180) throw InputError("", "--pose-error-deg must be in [0, 180]");
    if (o.pose_error_mm < 0) throw InputError("", "--pose-error-mm must be >= 0");
    if (o.cables < 0 || o.cables > 3) throw InputError("", "--cables must be 1, 2 or 3");
    if (!o.cable_diameter_mm.empty() &&
        !(o.cable_diameter_mm[0] >= 0.5 && o.cable_diameter_mm[0] <= o.cable_diameter_mm[1] &&
          o.cable_diameter_mm[1] <= 40.0))
      throw InputError("", "--cable-diameter-mm needs LO HI with 0.5 <= LO <= HI <= 40");
    if (o.campaign < 0 || o.campaign > 100000) throw InputError("", "--campaign must be in [0, 100000]");
    if (o.campaign > 0 && (!o.viewpoints.empty() || !o.cad.empty()))
      throw InputError("", "--campaign cannot be combined with --viewpoints or --cad");
    if (o.cad.empty() != o.plan.empty()) throw InputError("", "--cad and --plan go together");
    if (!o.clearance_with.empty() && o.defect != "clearance")
      throw InputError("", "--clearance-with needs --defect clearance");
    if (o.scene_only && !o.cad.empty()) throw InputError("", "--scene-only generates a scene; it cannot take --cad");

    sim::SimulateOptions so;
    so.scene.seed = o.seed;
    so.scene.defect = o.defect.empty() ? sim::DefectKind::None : *sim::parse_defect_kind(o.defect);
    so.scene.clearance_with = o.clearance_with;
    so.scene.cables = o.cables;
    if (!o.cable_diameter_mm.empty()) so.scene.cable_diameter_mm = {o.cable_diameter_mm[0], o.cable_diameter_mm[1]};
    so.sensor.sigma600_mm = o.noise_mm;
    so.sensor.outlier_fraction = o.outliers;
    so.sensor.noise_free = o.noise_free;
    so.sensor.mismatch_patches = o.mismatch_patches;
    so.pose_error_deg = o.pose_error_deg;
    so.pose_error_mm = o.pose_error_mm;
    so.scene_only = o.scene_only;
    std::optional<Pose> viewpoint;
    if (!o.viewpoints.empty()) viewpoint = sim::read_viewpoint_pose(o.viewpoints, o.rank);
    const ProgressFn progress = make_progress(common);

    if (!o.cad.empty()) {
      const fs::path dir = fs::path(o.cad).parent_path();
      const auto beside = [&](const std::string& given, const char* name) {
        if (!given.empty()) return given;
        const fs::path p = dir / name;
        return fs::exists(p) ? p.string() : std::string();
      };
      const std::string asbuilt = beside(o.asbuilt, "asbuilt.obj");
      const std::string truth = beside(o.scene_truth, "scene_truth.json");
      Pose pose;
      if (viewpoint) {
        pose = *viewpoint;
      } else if (!truth.empty()) {
        pose = sim::read_truth_pose(truth);
      } else {
        throw InputError(o.cad, "no camera pose: give --viewpoints (or a scene_truth.json beside the CAD)");
      }
      ensure_directory(o.out);
      const auto s = sim::write_scan_of_cad(o.out, o.cad, o.plan, asbuilt, truth, pose, so, o.seed);
      log(common, "simulate " + summary_line(s));
      return 0;
    }

    so.camera_to_cad = viewpoint;
    if (o.campaign > 0) {
      const sim::DefectKind forced = o.defect.empty() ? sim::DefectKind::Random : so.scene.defect;
      so.scene.defect = sim::DefectKind::None;
      const auto scenes = sim::write_campaign(o.out, static_cast<std::size_t>(o.campaign), so, forced, progress);
      std::size_t with = 0;
      double scan_s = 0;
      for (const auto& s : scenes) {
        if (s.defects > 0) ++with;
        scan_s += s.scan_seconds;
        if (!common.quiet) log(common, "simulate " + summary_line(s));
      }
      std::ostringstream m;
      m.precision(3);
      m << "campaign: " << scenes.size() << " scenes in " << o.out << ", " << with << " with defects, mean scan "
        << (scenes.empty() ? 0.0 : scan_s / scenes.size()) << " s";
      log(common, m.str());
      return 0;
    }
    const auto s = sim::write_scene(o.out, so, progress);
    log(common, "simulate " + summary_line(s));
    return 0;
  };
  return cmd;
}

}  // namespace ewis::cli
