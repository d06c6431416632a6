// Whether a scan shows both surfaces of each gap (see gap_visibility.hpp).
#include "ewis/sim/gap_visibility.hpp"

#include <algorithm>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

#include "ewis/core/cylinder.hpp"

namespace ewis::sim {

void mark_seen_gaps(SimScene& sim, const Scene& built, const ScanResult& scan, const Pose& camera_to_cad,
                    const GapSeenParams& params) {
  // The surface points of each element, in the CAD's frame.
  std::vector<std::vector<Eigen::Vector3d>> on(built.elements.size());
  for (std::size_t i = 0; i < scan.cloud.size() && i < scan.kind.size() && i < scan.element.size(); ++i)
    if (scan.kind[i] == PointKind::Surface && scan.element[i] < on.size())
      on[scan.element[i]].push_back(camera_to_cad * scan.cloud.points[i].cast<double>());
  std::unordered_map<std::string, std::size_t> index;
  for (std::size_t e = 0; e < built.elements.size(); ++e) index.emplace(built.elements[e].name, e);
  const auto points_of = [&](const std::string& name) -> const std::vector<Eigen::Vector3d>* {
    const auto it = index.find(name);
    return it == index.end() ? nullptr : &on[it->second];
  };
  const auto enough = [&](const std::vector<Eigen::Vector3d>& pts, const auto& keep) {
    std::size_t n = 0;
    for (const Eigen::Vector3d& p : pts)
      if (keep(p) && ++n >= params.min_points) return true;
    return false;
  };
  // `line`: the cable's sampled centreline
  const auto seen = [&](const SimCable& cable, const std::vector<Eigen::Vector3d>& line, const SimGap& g) {
    const std::vector<Eigen::Vector3d>* mine = points_of(cable.name);
    const std::vector<Eigen::Vector3d>* theirs = points_of(g.with);
    if (!mine || !theirs) return false;
    const double r = 0.5 * cable.diameter_mm;
    const double cable_reach = r + params.cable_reach_mm;
    if (!enough(*mine, [&](const Eigen::Vector3d& p) { return (p - g.location).norm() <= cable_reach; })) return false;
    // The other's points within gap + other_within_mm of the cable's surface, looked for within `ball` of the gap.
    const double within = r + std::max(g.gap_mm, 0.0) + params.other_within_mm;
    const double ball = within + 5.0;
    std::vector<Cylinder> near;  // centreline pieces that may hold the nearest point to a point in the ball
    for (std::size_t i = 0; i + 1 < line.size(); ++i)
      if (std::min((line[i] - g.location).norm(), (line[i + 1] - g.location).norm()) <= ball + within + 1.0)
        near.push_back(Cylinder{line[i], line[i + 1], 0.0});
    return enough(*theirs, [&](const Eigen::Vector3d& p) {
      if ((p - g.location).norm() > ball) return false;
      double d = std::numeric_limits<double>::infinity();
      for (const Cylinder& piece : near) d = std::min(d, distance_to_segment(piece, p));
      return d <= within;
    });
  };
  for (const SimCable& cable : sim.cables) {
    std::vector<Eigen::Vector3d> line;  // sampled once a gap of the cable is looked at
    for (SimGap& g : sim.gaps) {
      if (g.cable != cable.name || g.gap_mm > cable.clearance_mm + params.max_gap_over_clearance_mm) continue;
      if (line.empty()) line = sample_route(cable.as_built, 0.5);
      g.seen = seen(cable, line, g);
    }
  }
  for (SimDefect& d : sim.defects)
    if (d.kind == "clearance" || d.kind == "foreign_object")
      for (const SimGap& g : sim.gaps)  // the defect is one of the cable's gaps
        if (g.cable == d.element && g.location == d.location && g.gap_mm == d.gap_mm) d.seen = g.seen;
}

}  // namespace ewis::sim
