// One inspection into an output folder: read and check every input first (no partial output on bad input),
// inspect, then write report.json, report.html and the coloured PLY files.
#include "ewis/report/run_inspection.hpp"

#include <chrono>

#include "ewis/core/error.hpp"
#include "ewis/io/plan_file.hpp"
#include "ewis/io/pose_file.hpp"
#include "ewis/scene/scene.hpp"

namespace ewis {

InspectionRun run_inspection(const InspectionInputs& in, const std::string& out_dir, const RunInspectionParams& params,
                             const ProgressFn& progress) {
  using clock = std::chrono::steady_clock;
  const auto seconds = [](clock::time_point a, clock::time_point b) { return std::chrono::duration<double>(b - a).count(); };
  InspectionRun run;
  const auto t0 = clock::now();
  run.plan = read_plan(in.plan);
  const Scene scene = load_scene(in.cad);
  check_plan_against_scene(run.plan, scene, in.plan);
  CloudFile scan = read_cloud(in.scan, in.scan_unit);
  std::optional<Pose> pose;
  if (!in.pose.empty()) pose = read_pose(in.pose);
  if (scan.cloud.empty()) throw InputError(in.scan, "no finite points");
  const auto t1 = clock::now();
  run.load_seconds = seconds(t0, t1);

  run.result = inspect(scene, run.plan, std::move(scan.cloud), pose, params.inspect, progress);
  run.report_json = report_to_json(run.result, run.plan);
  const auto t2 = clock::now();
  run.inspect_seconds = seconds(t1, t2);

  ReportFiles files;
  files.html = params.write_html;
  files.clouds = params.write_clouds;
  files.json = false;  // written last, below, from the text already made
  ReportParams rp = params.report;
  if (rp.scan_name.empty()) rp.scan_name = in.scan;
  if (progress) progress("report", 0.0);
  write_report_files(run.result, scene, run.plan, out_dir, files, rp);
  write_file_atomic(out_dir + "/report.json", run.report_json);
  if (progress) progress("report", 1.0);
  run.write_seconds = seconds(t2, clock::now());
  return run;
}

}  // namespace ewis
