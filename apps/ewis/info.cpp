// ewis info: one JSON object about a scan (CONTRACT.md "ewis info").
#include <iostream>

#include "common.hpp"
#include "ewis/filter/noise_correlation.hpp"
#include "ewis/filter/resolution.hpp"
#include "ewis/register/sensor_origin.hpp"
#include "ewis/io/cloud_io.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis::cli {

Command add_info(CLI::App& root, CommonOptions& common) {
  struct Options {
    std::string scan;
    std::string units = "mm";
  };
  auto opt = std::make_shared<Options>();
  Command cmd;
  cmd.app = root.add_subcommand("info", "Print point count, fields, bounds and resolution of a scan as JSON");
  cmd.app->add_option("--scan", opt->scan, "Point cloud (PLY, PCD, XYZ)")->required();
  cmd.app->add_option("--scan-units", opt->units, "Units of the scan: mm, m or in")->check(CLI::IsMember({"mm", "m", "in"}));
  add_common_options(cmd.app, common);
  cmd.run = [opt, &common]() -> int {
    const CloudFile file = read_cloud(opt->scan, parse_length_unit(opt->units));
    nlohmann::json out;
    out["points"] = file.cloud.size();
    out["dropped_nonfinite"] = file.dropped_nonfinite;
    out["fields"] = file.fields;
    Eigen::Vector3f lo, hi;
    if (bounds(file.cloud.points, lo, hi)) {
      out["bounds_min"] = to_json_vec3(lo.x(), lo.y(), lo.z());
      out["bounds_max"] = to_json_vec3(hi.x(), hi.y(), hi.z());
    } else {
      out["bounds_min"] = nullptr;
      out["bounds_max"] = nullptr;
    }
    if (file.cloud.size() >= 2) {
      const KdTree tree(file.cloud.points);
      const ResolutionResult resolution = spatial_resolution(tree);
      out["resolution_mm"] = resolution.mean_mm;
      // How much neighbouring points' noise moves together (filter/noise_correlation.hpp): 1 for independent noise.
      const NoiseCorrelation nc = estimate_noise_correlation(tree, resolution.median_mm);
      out["noise_sigma_mm"] = nc.sigma_mm > 0.0 ? nlohmann::json(nc.sigma_mm) : nlohmann::json(nullptr);
      out["noise_inflation"] = nc.inflation;
      out["noise_patches"] = nc.patches;
    } else {
      out["resolution_mm"] = nullptr;
    }
    // How far the scan is from a depth image seen from its origin, as the inspection assumes it is
    // (register/sensor_origin.hpp; on the raw scan, outliers included: a sensor-frame scan with 40 % outliers 0.31,
    // the same in CAD coordinates 1.0).
    // Measured in the contract's camera frame, as `inspect` turns a scan written in another convention
    // (register/sensor_origin.hpp `scan_convention`: "-z" with y up as OpenGL's, "+x" as a ROS body frame).
    const ScanConvention convention = scan_convention(file.cloud.points);
    out["looks_along"] = convention.looks_along;
    out["occluded_from_origin"] = occluded_from_origin(file.cloud.points, convention);
    if (file.height > 1) {
      out["width"] = file.width;
      out["height"] = file.height;
    }
    std::cout << out.dump() << std::endl;
    return 0;
  };
  return cmd;
}

}  // namespace ewis::cli
