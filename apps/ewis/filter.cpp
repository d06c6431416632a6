// ewis filter: radius outlier removal (paper 4.1.1), CONTRACT.md "ewis filter".
#include <cmath>
#include <iostream>

#include "common.hpp"
#include "ewis/core/error.hpp"
#include "ewis/filter/outlier_removal.hpp"
#include "ewis/io/cloud_io.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis::cli {

Command add_filter(CLI::App& root, CommonOptions& common) {
  struct Options {
    std::string scan, out;
    std::string units = "mm";
    double radius_mm = 0.0;
    int min_neighbors = -1;
  };
  auto opt = std::make_shared<Options>();
  Command cmd;
  cmd.app = root.add_subcommand("filter", "Radius outlier removal; writes the kept points as binary PLY");
  cmd.app->add_option("--scan", opt->scan, "Input point cloud (PLY, PCD, XYZ)")->required();
  cmd.app->add_option("--out", opt->out, "Output binary PLY")->required();
  cmd.app->add_option("--radius-mm", opt->radius_mm, "Sphere radius R (default: 4 x measured resolution)")
      ->check(CLI::PositiveNumber);
  cmd.app->add_option("--min-neighbors", opt->min_neighbors, "Least number K of other points within R (default: derived)")
      ->check(CLI::NonNegativeNumber);
  cmd.app->add_option("--scan-units", opt->units, "Units of the scan: mm, m or in")->check(CLI::IsMember({"mm", "m", "in"}));
  add_common_options(cmd.app, common);
  cmd.run = [opt, &common]() -> int {
    if (!std::isfinite(opt->radius_mm)) throw InputError("", "--radius-mm must be a finite positive number");
    const CloudFile file = read_cloud(opt->scan, parse_length_unit(opt->units));
    if (file.cloud.empty()) throw InputError(opt->scan, "no finite points (" + std::to_string(file.dropped_nonfinite) +
                                                            " non-finite dropped)");
    log(common, opt->scan + ": " + std::to_string(file.cloud.size()) + " points");
    const KdTree tree(file.cloud.points);
    RadiusOutlierParams params;
    params.radius_mm = opt->radius_mm;
    params.min_neighbors = opt->min_neighbors;
    const RadiusOutlierResult result = remove_radius_outliers(tree, params);
    write_ply(select(file.cloud, result.kept), opt->out);
    nlohmann::json line = {{"points_in", file.cloud.size()},
                           {"points_out", result.kept.size()},
                           {"radius_mm", result.radius_mm},
                           {"min_neighbors", result.min_neighbors}};
    if (result.resolution_mm > 0) line["resolution_mm"] = result.resolution_mm;
    std::cout << line.dump() << std::endl;
    return 0;
  };
  return cmd;
}

}  // namespace ewis::cli
