#include "common.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <mutex>

#include "ewis/core/error.hpp"

namespace ewis::cli {

void add_common_options(CLI::App* sub, CommonOptions& common) {
  sub->add_option("--threads", common.threads, "Worker threads (default: all cores); results do not depend on it")
      ->check(CLI::NonNegativeNumber);
  sub->add_flag("--quiet,-q", common.quiet, "No progress messages on stderr");
}

ProgressFn make_progress(const CommonOptions& common) {
  if (common.quiet) return {};
  struct State {
    std::mutex mutex;
    std::string stage;
    int last_pct = -1;
    std::chrono::steady_clock::time_point last = std::chrono::steady_clock::now();
  };
  auto state = std::make_shared<State>();
  return [state](std::string_view stage, double fraction) {
    std::lock_guard<std::mutex> lock(state->mutex);
    const int pct = static_cast<int>(std::lround(std::clamp(fraction, 0.0, 1.0) * 100.0));
    const auto now = std::chrono::steady_clock::now();
    const bool new_stage = stage != state->stage;
    if (!new_stage && pct == state->last_pct) return;
    if (!new_stage && pct != 100 && now - state->last < std::chrono::milliseconds(500)) return;
    state->stage = std::string(stage);
    state->last_pct = pct;
    state->last = now;
    std::cerr << "ewis: [" << stage << "] " << pct << "%\n";
  };
}

void log(const CommonOptions& common, const std::string& message) {
  if (!common.quiet) std::cerr << "ewis: " << message << "\n";
}

nlohmann::json to_json_vec3(double x, double y, double z) { return nlohmann::json::array({x, y, z}); }

void ensure_directory(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) throw InputError(dir, "exists and is not a directory");
  fs::create_directories(dir, ec);
  if (ec) throw InputError(dir, "cannot create directory: " + ec.message());
}

void check_scan_units(const std::vector<Eigen::Vector3f>& points, const std::string& path, const std::string& units) {
  if (units != "mm" || points.size() < 100) return;
  Eigen::Vector3f lo = points.front(), hi = points.front();
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double diagonal = (hi - lo).norm();
  if (diagonal < 10.0)
    throw InputError(path, "the scan spans only " + std::to_string(diagonal) +
                               " mm: it looks like metres or inches, pass --scan-units m (or in)");
}

}  // namespace ewis::cli
