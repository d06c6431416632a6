#pragma once
// report.html (issue 6, item 3; CONTRACT.md "ewis inspect"): ONE self-contained file (inline CSS, pictures as
// base64 PNG data URIs, no scripts, no external resources) that a person opens offline: the verdict, a table
// per cable and per rule (measured against allowed, pass/fail coloured), the scan as the sensor saw it and a
// close-up of each defect. Times (which report.json must not hold) may appear here.
#include <string>
#include <vector>

#include "ewis/inspect/pipeline.hpp"
#include "ewis/io/plan_file.hpp"
#include "ewis/scene/scene.hpp"

namespace ewis {

struct ReportParams {
  std::string title = "EWIS inspection report";
  std::string scan_name;                // shown in the header (e.g. the scan file), optional
  int scan_image_width_px = 1024;       // main picture (the sensor's aspect)
  int closeup_width_px = 440;           // each close-up picture (two per defect: points, CAD)
  int closeup_height_px = 330;
  std::size_t max_closeups = 12;
  bool render_cad = true;               // ray-cast CAD close-ups (needs the scene's triangles)
  bool include_timings = true;          // result.timings in a small table
};

// The whole HTML text. `scene` is the CAD the result was inspected against (element names, ray casting).
std::string report_html(const InspectionResult& result, const Scene& scene, const InspectionPlan& plan,
                        const ReportParams& params = {});

struct ReportFiles {
  bool html = true;                     // report.html
  bool clouds = false;                  // cables.ply, interferences.ply, rest.ply (binary, coloured)
  bool json = false;                    // report.json (report_to_json of the inspect stage)
};

// Writes the chosen files into out_dir (created when missing); each file is written atomically. The scan,
// its labels and the registered sensor pose are those of `result` (result.cloud in CAD coordinates,
// result.cables[].trace.points / interferences[].points, result.scan_to_cad). Throws InputError when the
// folder cannot be written.
void write_report_files(const InspectionResult& result, const Scene& scene, const InspectionPlan& plan,
                        const std::string& out_dir, const ReportFiles& files = {}, const ReportParams& params = {});

// HTML text escaping (&, <, >, ", ').
std::string html_escape(const std::string& text);

}  // namespace ewis
