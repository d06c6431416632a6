// ewis plan: offline viewpoint selection (CONTRACT.md "ewis plan", paper 3, docs/plan.md).
#include <chrono>
#include <sstream>

#include "common.hpp"
#include "ewis/core/error.hpp"
#include "ewis/inspect/pipeline.hpp"
#include "ewis/io/plan_file.hpp"
#include "ewis/plan/viewpoint_plan.hpp"
#include "ewis/scene/scene.hpp"

namespace ewis::cli {
namespace {

// "MIN,MAX" in degrees.
void parse_range(const std::string& text, const char* option, double& lo, double& hi) {
  if (text.empty()) return;
  std::istringstream in(text);
  char comma = 0;
  if (!(in >> lo >> comma >> hi) || comma != ',' || !(in >> std::ws).eof())
    throw InputError("", std::string(option) + " expects MIN,MAX in degrees, got '" + text + "'");
}

}  // namespace

Command add_plan(CLI::App& root, CommonOptions& common) {
  struct Options {
    std::string cad, plan, out, theta, phi;
    std::vector<std::string> elements;
    double radius_mm = 0.0;
    double step_deg = 10.0;
    std::size_t top = 5;
    bool measurable = false;
    double min_distance_mm = -1.0;
    double coverage_target = 0.9;
    std::size_t coverage_samples = 2000;
    bool cover = false;
  };
  auto opt = std::make_shared<Options>();
  Command cmd;
  cmd.app = root.add_subcommand("plan", "Offline viewpoint selection: score candidate sensor poses on a sphere "
                                        "around an element and write the best (viewpoints.json + PNGs)");
  auto* app = cmd.app;
  app->add_option("--cad", opt->cad, "CAD scene (OBJ, STL, PLY, glTF, ...), one object per element")->required();
  app->add_option("--plan", opt->plan, "Inspection plan (JSON): the sensor model and the cables")->required();
  app->add_option("--element", opt->elements,
                  "Element to inspect (repeat for several, or 'all-cables' for every cable of the plan: "
                  "then a small covering set of viewpoints is chosen too)")
      ->required()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
      ->allow_extra_args(false);
  app->add_option("--out", opt->out, "Output folder")->required();
  app->add_option("--radius", opt->radius_mm, "Candidate sphere radius in mm (default: the plan's standoff_mm)")
      ->check(CLI::NonNegativeNumber);
  app->add_option("--step", opt->step_deg, "Angular step of theta and phi in degrees (default 10)")
      ->check(CLI::PositiveNumber);
  app->add_option("--top", opt->top, "Number of best views to keep (default 5)")->check(CLI::Range(1, 100000));
  app->add_option("--theta", opt->theta, "Longitude range MIN,MAX in degrees (default 0,360)");
  app->add_option("--phi", opt->phi, "Colatitude range MIN,MAX in degrees, within 0..180 (default 0,180)");
  app->add_flag("--measurable", opt->measurable,
                "Score only pixels the structured-light sensor can measure (seen, lit by the projector 100 mm "
                "along camera x, incidence below 75 deg)");
  app->add_option("--min-distance", opt->min_distance_mm,
                  "Reject candidates with CAD geometry closer than this (mm; default half the radius, 0: only "
                  "reject positions inside geometry)")
      ->check(CLI::NonNegativeNumber);
  app->add_option("--coverage-target", opt->coverage_target,
                  "Fraction of each element's surface the covering set must see (default 0.9)")
      ->check(CLI::Range(0.0, 1.0));
  app->add_option("--coverage-samples", opt->coverage_samples, "Surface samples per element for coverage (default 2000)")
      ->check(CLI::Range(1, 1000000));
  app->add_flag("--cover", opt->cover, "Compute the covering set even for a single element");
  add_common_options(app, common);
  cmd.run = [opt, &common]() -> int {
    const auto t0 = std::chrono::steady_clock::now();
    ViewpointParams params;
    params.candidates.radius_mm = opt->radius_mm;
    params.candidates.step_deg = opt->step_deg;
    parse_range(opt->theta, "--theta", params.candidates.theta_min_deg, params.candidates.theta_max_deg);
    parse_range(opt->phi, "--phi", params.candidates.phi_min_deg, params.candidates.phi_max_deg);
    params.top = opt->top;
    params.score.measurable = opt->measurable;
    params.score.min_distance_mm = opt->min_distance_mm;
    params.coverage.target_fraction = opt->coverage_target;
    params.coverage.samples_per_element = opt->coverage_samples;
    params.force_coverage = opt->cover;

    const InspectionPlan plan = read_plan(opt->plan);
    const Scene scene = load_scene(opt->cad);
    const std::vector<std::uint32_t> elements = resolve_elements(scene, plan, opt->elements, opt->cad, opt->plan);
    check_cad_units(plan, scene, opt->cad);
    if (!(params.candidates.radius_mm > 0)) params.candidates.radius_mm = plan.sensor.standoff_mm;
    // Validate the sampling options before any work (exit 2, nothing written).
    (void)theta_samples_deg(params.candidates);
    (void)phi_samples_deg(params.candidates);
    log(common, "plan: " + std::to_string(scene.triangle_count()) + " triangles, " +
                    std::to_string(elements.size()) + " element(s)");

    const ProgressFn progress = make_progress(common);
    const ViewpointPlan result = plan_viewpoints(scene, plan.sensor, elements, params, progress);
    ensure_directory(opt->out);
    write_viewpoint_outputs(scene, result, opt->out, progress);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::ostringstream msg;
    msg << "plan: wrote " << opt->out << "/viewpoints.json";
    if (!result.best.empty()) {
      const auto& b = result.best.front();
      msg << " (best " << result.elements[b.first].scores[b.second].score_px << " px)";
    }
    if (result.has_coverage)
      msg << "; covering set of " << result.coverage.viewpoints.size() << " view(s)"
          << (result.coverage.complete ? "" : " (target not reached)");
    msg << " in " << seconds << " s";
    log(common, msg.str());
    return 0;
  };
  return cmd;
}

}  // namespace ewis::cli
