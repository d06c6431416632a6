// Writing the report's files into a folder, each atomically (CONTRACT.md: whole or not at all).
#include <filesystem>

#include "ewis/core/error.hpp"
#include "ewis/io/cloud_io.hpp"
#include "ewis/report/report_html.hpp"

namespace ewis {

void write_report_files(const InspectionResult& result, const Scene& scene, const InspectionPlan& plan,
                        const std::string& out_dir, const ReportFiles& files, const ReportParams& params) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(out_dir, ec) && !fs::is_directory(out_dir, ec)) throw InputError(out_dir, "exists and is not a directory");
  fs::create_directories(out_dir, ec);
  if (ec) throw InputError(out_dir, "cannot create directory: " + ec.message());
  // Everything is computed before the first file is written.
  std::string html, json;
  if (files.html) html = report_html(result, scene, plan, params);
  if (files.json) json = report_to_json(result, plan);
  if (files.clouds) {
    write_result_clouds(result, out_dir);
  }
  if (files.html) write_file_atomic(out_dir + "/report.html", html);
  if (files.json) write_file_atomic(out_dir + "/report.json", json);
}

}  // namespace ewis
