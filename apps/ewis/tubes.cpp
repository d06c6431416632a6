// ewis tubes: trace tubes (cables, hoses, pipes, branches) from seed points without a CAD (CONTRACT.md
// "ewis tubes"; paper 4.2). Writes DIR/tubes.json and DIR/tubes.ply (points coloured per tube, others grey).
#include <cmath>
#include <sstream>

#include "common.hpp"
#include "ewis/core/error.hpp"
#include "ewis/filter/outlier_removal.hpp"
#include "ewis/io/cloud_io.hpp"
#include "ewis/search/kdtree.hpp"
#include "ewis/tubes/trace.hpp"

namespace ewis::cli {
namespace {

Eigen::Vector3d parse_point(const std::string& text, const std::string& option) {
  std::stringstream ss(text);
  std::string part;
  std::vector<double> v;
  while (std::getline(ss, part, ',')) {
    try {
      std::size_t used = 0;
      v.push_back(std::stod(part, &used));
      if (used != part.size() && part.find_first_not_of(" \t", used) != std::string::npos) v.push_back(NAN);
    } catch (const std::exception&) {
      v.push_back(NAN);
    }
  }
  if (v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
    throw InputError("", option + " '" + text + "': expected X,Y,Z (three numbers)");
  return {v[0], v[1], v[2]};
}

// Fixed decimals keep the file short and byte-identical across runs.
double round4(double x) { return std::round(x * 1e4) / 1e4; }
nlohmann::json vec(const Eigen::Vector3d& p) { return nlohmann::json::array({round4(p.x()), round4(p.y()), round4(p.z())}); }

nlohmann::json tube_json(const TubeTrace& t) {
  nlohmann::json j;
  j["seed"] = vec(t.seed);
  j["found"] = t.found;
  j["radius_mm"] = t.found ? nlohmann::json(round4(t.radius_mm)) : nlohmann::json(nullptr);
  j["length_mm"] = t.found ? nlohmann::json(round4(t.length_mm)) : nlohmann::json(nullptr);
  j["points"] = t.points.size();
  j["centerline"] = nlohmann::json::array();
  for (const auto& p : t.centerline) j["centerline"].push_back(vec(p));
  j["segments"] = nlohmann::json::array();
  for (const auto& s : t.segments)
    j["segments"].push_back({{"start", vec(s.cylinder.start)},
                             {"end", vec(s.cylinder.end)},
                             {"radius_mm", round4(s.cylinder.radius_mm)},
                             {"points", s.points},
                             {"rms_mm", round4(s.rms_mm)},
                             {"bridged", s.bridged}});
  j["gaps"] = nlohmann::json::array();
  for (const auto& g : t.gaps) j["gaps"].push_back({{"start", vec(g.start)}, {"end", vec(g.end)}});
  if (t.found) {
    j["rms_mm"] = round4(t.rms_mm);
    j["end_reasons"] = {t.end_reason_front, t.end_reason_back};
  }
  return j;
}

Rgb palette(std::size_t k) {
  static const Rgb colors[] = {{230, 25, 75},  {60, 180, 75},  {0, 130, 200},  {245, 130, 48}, {145, 30, 180},
                               {70, 240, 240}, {240, 50, 230}, {210, 245, 60}, {0, 128, 128}, {170, 110, 40}};
  return colors[k % 10];
}

}  // namespace

Command add_tubes(CLI::App& root, CommonOptions& common) {
  struct Options {
    std::string scan, out;
    std::vector<std::string> seeds;
    std::string units = "mm";
    std::string sensor;
    double radius_mm = 0.0;
    double max_gap_mm = 0.0;
  };
  auto opt = std::make_shared<Options>();
  Command cmd;
  cmd.app = root.add_subcommand("tubes", "Trace tubes (cables, hoses, pipes, branches) from seed points, no CAD needed");
  cmd.app->add_option("--scan", opt->scan, "Point cloud (PLY, PCD, XYZ)")->required();
  cmd.app->add_option("--seed", opt->seeds, "A point on or near a tube, X,Y,Z in the scan's frame (mm); repeatable")
      ->required()
      ->allow_extra_args(false);
  cmd.app->add_option("--radius-mm", opt->radius_mm, "Expected tube radius (a hint; default: estimated at the seed)")
      ->check(CLI::PositiveNumber);
  cmd.app->add_option("--max-gap-mm", opt->max_gap_mm, "Longest stretch bridged without data (default: 3 diameters)")
      ->check(CLI::PositiveNumber);
  cmd.app->add_option("--sensor", opt->sensor, "Sensor position X,Y,Z (mm): fit residuals along the camera rays");
  cmd.app->add_option("--out", opt->out, "Output folder (tubes.json, tubes.ply)")->required();
  cmd.app->add_option("--scan-units", opt->units, "Units of the scan: mm, m or in")->check(CLI::IsMember({"mm", "m", "in"}));
  add_common_options(cmd.app, common);
  cmd.run = [opt, &common]() -> int {
    std::vector<Eigen::Vector3d> seeds;
    for (const auto& s : opt->seeds) seeds.push_back(parse_point(s, "--seed"));
    TubeParams params;
    params.radius_mm = opt->radius_mm;
    params.max_gap_mm = opt->max_gap_mm;
    if (!opt->sensor.empty()) {
      params.has_sensor = true;
      params.sensor_position = parse_point(opt->sensor, "--sensor");
    }
    const CloudFile file = read_cloud(opt->scan, parse_length_unit(opt->units));
    if (file.cloud.empty()) throw InputError(opt->scan, "no points");
    check_scan_units(file.cloud.points, opt->scan, opt->units);
    ensure_directory(opt->out);
    log(common, opt->scan + ": " + std::to_string(file.cloud.size()) + " points");
    // paper 4.1.1: radius outlier removal first, parameters derived from the measured resolution
    const KdTree raw_tree(file.cloud.points);
    const RadiusOutlierResult kept = remove_radius_outliers(raw_tree, {});
    const Cloud cloud = select(file.cloud, kept.kept);
    const KdTree tree(cloud.points);
    log(common, "outlier removal kept " + std::to_string(kept.kept.size()) + " points");
    const ProgressFn progress = make_progress(common);
    std::vector<TubeTrace> tubes;
    for (std::size_t k = 0; k < seeds.size(); ++k) {
      // a seed on a tube already traced gives that same tube (CONTRACT.md: two seeds, same tube)
      const Neighbor nb = tree.nearest(seeds[k].cast<float>());
      const TubeTrace* same = nullptr;
      for (const TubeTrace& t : tubes)
        if (t.found && nb.index < cloud.size() && std::binary_search(t.points.begin(), t.points.end(), nb.index)) {
          same = &t;
          break;
        }
      if (same) {
        tubes.push_back(*same);
        tubes.back().seed = seeds[k];
      } else {
        tubes.push_back(trace_tube(cloud, tree, seeds[k], params));
      }
      const TubeTrace& t = tubes.back();
      if (t.found) {
        std::ostringstream line;
        line.precision(4);
        line << "tube " << k + 1 << ": radius " << t.radius_mm << " mm, length " << t.length_mm << " mm, "
             << t.segments.size() << " sub-cables, " << t.gaps.size() << " gaps, ends: " << t.end_reason_front << " / "
             << t.end_reason_back;
        log(common, line.str());
      } else {
        log(common, "tube " + std::to_string(k + 1) + ": no tube found at the seed");
      }
      if (progress) progress("tubes", static_cast<double>(k + 1) / seeds.size());
    }
    nlohmann::json out;
    out["tubes"] = nlohmann::json::array();
    for (const auto& t : tubes) out["tubes"].push_back(tube_json(t));
    // the scan's points coloured by tube (the first tube claiming a point wins), all others grey
    Cloud coloured = file.cloud;
    coloured.colors.assign(coloured.size(), Rgb{128, 128, 128});
    std::vector<char> taken(coloured.size(), 0);
    for (std::size_t k = 0; k < tubes.size(); ++k)
      for (std::uint32_t i : tubes[k].points) {
        const std::uint32_t orig = kept.kept[i];
        if (taken[orig]) continue;
        taken[orig] = 1;
        coloured.colors[orig] = palette(k);
      }
    write_ply(coloured, opt->out + "/tubes.ply");
    write_file_atomic(opt->out + "/tubes.json", out.dump(1) + "\n");
    return 0;
  };
  return cmd;
}

}  // namespace ewis::cli
