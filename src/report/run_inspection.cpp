// One inspection into an output folder: read and check every input first (no partial output on bad input),
// inspect, then write report.json, report.html and the coloured PLY files.
#include "ewis/report/run_inspection.hpp"

#include <tbb/parallel_invoke.h>

#include <chrono>
#include <exception>

#include "ewis/core/error.hpp"
#include "ewis/io/plan_file.hpp"
#include "ewis/io/pose_file.hpp"
#include "ewis/scene/scene.hpp"

namespace ewis {

LoadedInputs load_inspection_inputs(const InspectionInputs& in) {
  LoadedInputs out;
  out.plan = read_plan(in.plan);
  std::exception_ptr scene_error, scan_error;
  tbb::parallel_invoke(
      [&] {
        try {
          out.scene = load_scene(in.cad);
          orient_rigid_faces(out.scene, out.plan);  // while the scan is read (inspect warns where it reversed faces)
        } catch (...) {
          scene_error = std::current_exception();
        }
      },
      [&] {
        try {
          out.scan = read_cloud(in.scan, in.scan_unit);
        } catch (...) {
          scan_error = std::current_exception();
        }
      });
  if (scene_error) std::rethrow_exception(scene_error);
  check_plan_against_scene(out.plan, out.scene, in.plan);
  check_cad_units(out.plan, out.scene, in.cad);
  if (scan_error) std::rethrow_exception(scan_error);
  if (!in.pose.empty()) out.pose = read_pose(in.pose);
  if (out.scan.cloud.empty()) throw InputError(in.scan, "no finite points");
  return out;
}

InspectionRun run_inspection(const InspectionInputs& in, const std::string& out_dir, const RunInspectionParams& params,
                             const ProgressFn& progress) {
  using clock = std::chrono::steady_clock;
  const auto seconds = [](clock::time_point a, clock::time_point b) { return std::chrono::duration<double>(b - a).count(); };
  InspectionRun run;
  const auto t0 = clock::now();
  LoadedInputs loaded = load_inspection_inputs(in);
  run.plan = std::move(loaded.plan);
  const Scene& scene = loaded.scene;
  const auto t1 = clock::now();
  run.load_seconds = seconds(t0, t1);

  run.result = inspect(scene, run.plan, std::move(loaded.scan.cloud), loaded.pose, params.inspect, progress);
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
