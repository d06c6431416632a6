// ewis inspect: the online inspection of CONTRACT.md ("ewis inspect"): loads, runs the inspect pipeline,
// writes DIR/report.json (atomic) and coloured PLY files (CAD coordinates); timings per step on stderr.
#include <chrono>
#include <cstdio>
#include <iostream>

#include "common.hpp"
#include "ewis/report/report_html.hpp"
#include "ewis/report/run_inspection.hpp"
#include "ewis/core/error.hpp"
#include "ewis/inspect/pipeline.hpp"
#include "ewis/io/cloud_io.hpp"

namespace ewis::cli {

Command add_inspect(CLI::App& root, CommonOptions& common) {
  struct Options {
    std::string cad, plan, scan, pose, out;
    std::string units = "mm";
  };
  auto opt = std::make_shared<Options>();
  Command cmd;
  cmd.app = root.add_subcommand(
      "inspect", "Inspect the cables of a scan against the CAD and plan: bend radius, clearance, verdict");
  cmd.app->add_option("--cad", opt->cad, "CAD scene (OBJ, STL, PLY, glTF...), one object per element")->required();
  cmd.app->add_option("--plan", opt->plan, "Inspection plan (JSON)")->required();
  cmd.app->add_option("--scan", opt->scan, "Point cloud in the sensor's frame (PLY, PCD, XYZ)")->required();
  cmd.app->add_option("--pose", opt->pose, "Initial scan-to-CAD pose: 16 numbers, 4x4 row-major (optional)");
  cmd.app->add_option("--out", opt->out, "Output directory (report.json, PLY files)")->required();
  cmd.app->add_option("--scan-units", opt->units, "Units of the scan: mm, m or in")
      ->check(CLI::IsMember({"mm", "m", "in"}));
  add_common_options(cmd.app, common);
  cmd.run = [opt, &common]() -> int {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    // Everything is read and checked before anything is written (no partial output on bad input).
    InspectionInputs inputs;
    inputs.cad = opt->cad, inputs.plan = opt->plan, inputs.scan = opt->scan, inputs.pose = opt->pose;
    inputs.scan_unit = parse_length_unit(opt->units);
    LoadedInputs loaded = load_inspection_inputs(inputs);
    const InspectionPlan& plan = loaded.plan;
    const Scene& scene = loaded.scene;
    CloudFile& scan = loaded.scan;
    const std::optional<Pose>& pose = loaded.pose;
    check_scan_units(scan.cloud.points, opt->scan, opt->units);
    const double load_s = std::chrono::duration<double>(clock::now() - t0).count();
    log(common, "loaded " + std::to_string(scan.cloud.size()) + " scan points, " +
                    std::to_string(scene.elements.size()) + " CAD elements");

    const InspectionResult result = inspect(scene, plan, std::move(scan.cloud), pose, InspectParams{}, make_progress(common));
    const std::string json = report_to_json(result, plan);
    for (const std::string& w : result.warnings) std::cerr << "ewis: warning: " << opt->scan << ": " << w << "\n";

    const auto tw = clock::now();
    ensure_directory(opt->out);
    write_result_clouds(result, opt->out);  // one at a time, before the report renders its pictures
    ReportParams report_params;
    report_params.scan_name = opt->scan;
    write_report_files(result, scene, plan, opt->out, ReportFiles{}, report_params);  // report.html
    write_file_atomic(opt->out + "/report.json", json);
    const double write_s = std::chrono::duration<double>(clock::now() - tw).count();

    // Timings go to stderr only (report.json stays byte-identical across runs and thread counts).
    if (!common.quiet) {
      char line[128];
      std::snprintf(line, sizeof line, "ewis: time load %.3f s", load_s);
      std::cerr << line << "\n";
      for (const StepTiming& t : result.timings) {
        std::snprintf(line, sizeof line, "ewis: time %s %.3f s", t.step.c_str(), t.seconds);
        std::cerr << line << "\n";
      }
      std::snprintf(line, sizeof line, "ewis: time write %.3f s, total %.3f s", write_s,
                    std::chrono::duration<double>(clock::now() - t0).count());
      std::cerr << line << "\n";
      std::size_t defects = 0;
      for (const CableInspection& c : result.cables)
        defects += (!c.found) + (c.bend_ok == false) + (c.clearance_ok == false);
      log(common, std::string("verdict ") + (result.pass ? "pass" : "fail") + " (" + std::to_string(defects) +
                      " failed checks); report: " + opt->out + "/report.json");
    }
    return 0;
  };
  return cmd;
}

}  // namespace ewis::cli
