#pragma once
// "Run one inspection into an output folder": what `ewis inspect` does and what `ewis evaluate` does for each
// scene, in one function: read the inputs (all checked before anything is written), inspect, write
// report.json, report.html and the coloured PLY files into out_dir.
#include <optional>
#include <string>

#include "ewis/core/progress.hpp"
#include "ewis/inspect/pipeline.hpp"
#include "ewis/io/cloud_io.hpp"
#include "ewis/report/report_html.hpp"
#include "ewis/scene/scene.hpp"

namespace ewis {

struct InspectionInputs {
  std::string cad, plan, scan;
  std::string pose;                     // empty: no initial pose (global registration)
  LengthUnit scan_unit = LengthUnit::Millimetre;
};

// The inputs read and checked, ready for inspect().
struct LoadedInputs {
  InspectionPlan plan;
  Scene scene;
  CloudFile scan;
  std::optional<Pose> pose;
};

// Reads the plan, then the CAD and the scan at once (each a file parse of its own, on two threads), then the pose.
// Errors (InputError) come as a one-at-a-time read reports them: the plan's, the CAD's, the plan against the CAD,
// the scan's, the pose's, a scan without finite points.
LoadedInputs load_inspection_inputs(const InspectionInputs& inputs);

struct RunInspectionParams {
  InspectParams inspect;
  ReportParams report;
  bool write_html = true;
  bool write_clouds = true;
};

struct InspectionRun {
  InspectionResult result;
  InspectionPlan plan;
  std::string report_json;              // as written to out_dir/report.json
  double load_seconds = 0.0, inspect_seconds = 0.0, write_seconds = 0.0;
};

// Throws InputError (bad inputs; nothing is written) or ProcessingError (could not finish).
InspectionRun run_inspection(const InspectionInputs& inputs, const std::string& out_dir,
                             const RunInspectionParams& params = {}, const ProgressFn& progress = {});

}  // namespace ewis
