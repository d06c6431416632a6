#pragma once
// Shared by the subcommands: the options every command takes, progress on stderr, JSON output.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ewis/core/progress.hpp"

namespace ewis::cli {

struct CommonOptions {
  int threads = 0;     // 0: all cores
  bool quiet = false;  // no progress on stderr
};

// A subcommand: its CLI11 app and the function that runs it once parsed (returns the exit code).
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

// Adds --threads and --quiet to a subcommand.
void add_common_options(CLI::App* sub, CommonOptions& common);

// A progress callback that prints "[stage] 42%" lines on stderr (nothing when quiet).
ProgressFn make_progress(const CommonOptions& common);
// One log line on stderr ("ewis: ..."), unless quiet.
void log(const CommonOptions& common, const std::string& message);

// JSON array from a 3-vector / 4x4 matrix.
nlohmann::json to_json_vec3(double x, double y, double z);

// Creates directory `dir` (and parents); throws InputError when it exists as a file or cannot be made.
void ensure_directory(const std::string& dir);

// A scan read with --scan-units mm whose extent is tiny is almost surely in metres (PCL/ROS clouds): refuse it with a
// clear message instead of failing later. Throws InputError(path, ...) when the bounding-box diagonal of a cloud
// of at least 100 points is under 10 mm while `units` is "mm".
void check_scan_units(const std::vector<Eigen::Vector3f>& points, const std::string& path, const std::string& units);

// Each subcommand file defines one of these.
Command add_info(CLI::App& root, CommonOptions& common);
Command add_filter(CLI::App& root, CommonOptions& common);
Command add_register(CLI::App& root, CommonOptions& common);
Command add_tubes(CLI::App& root, CommonOptions& common);
Command add_simulate(CLI::App& root, CommonOptions& common);
Command add_inspect(CLI::App& root, CommonOptions& common);
Command add_plan(CLI::App& root, CommonOptions& common);
Command add_evaluate(CLI::App& root, CommonOptions& common);

}  // namespace ewis::cli
