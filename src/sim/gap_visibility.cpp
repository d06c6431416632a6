// Whether a scan shows both surfaces of each gap (see gap_visibility.hpp).
#include "ewis/sim/gap_visibility.hpp"

#include <algorithm>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

namespace ewis::sim {

namespace {

double segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

}  // namespace

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
  const auto seen = [&](const std::string& cable_name, const std::string& other, double gap_mm,
                        const Eigen::Vector3d& location) {
    const auto cable = std::find_if(sim.cables.begin(), sim.cables.end(),
                                    [&](const SimCable& c) { return c.name == cable_name; });
    const std::vector<Eigen::Vector3d>* mine = points_of(cable_name);
    const std::vector<Eigen::Vector3d>* theirs = points_of(other);
    if (cable == sim.cables.end() || !mine || !theirs) return false;
    const double r = 0.5 * cable->diameter_mm;
    const auto enough = [&](const std::vector<Eigen::Vector3d>& pts, const auto& keep) {
      std::size_t n = 0;
      for (const Eigen::Vector3d& p : pts)
        if (keep(p) && ++n >= params.min_points) return true;
      return false;
    };
    const double cable_reach = r + params.cable_reach_mm;
    if (!enough(*mine, [&](const Eigen::Vector3d& p) { return (p - location).norm() <= cable_reach; })) return false;
    // The other's points within gap + other_within_mm of the cable's surface, looked for within `ball` of the gap.
    const double within = r + std::max(gap_mm, 0.0) + params.other_within_mm;
    const double ball = within + 5.0;
    const std::vector<Eigen::Vector3d> line = sample_route(cable->as_built, 0.5);
    std::vector<std::size_t> near;  // centreline samples that may be the nearest to a point in the ball
    for (std::size_t i = 0; i < line.size(); ++i)
      if ((line[i] - location).norm() <= ball + within + 1.0) near.push_back(i);
    return enough(*theirs, [&](const Eigen::Vector3d& p) {
      if ((p - location).norm() > ball) return false;
      double d = std::numeric_limits<double>::infinity();
      for (std::size_t i : near) {
        if (i + 1 < line.size()) d = std::min(d, segment_distance(p, line[i], line[i + 1]));
        if (i > 0) d = std::min(d, segment_distance(p, line[i - 1], line[i]));
      }
      return d <= within;
    });
  };
  for (SimGap& g : sim.gaps) {
    const auto cable = std::find_if(sim.cables.begin(), sim.cables.end(),
                                    [&](const SimCable& c) { return c.name == g.cable; });
    if (cable != sim.cables.end() && g.gap_mm <= cable->clearance_mm + params.max_gap_over_clearance_mm)
      g.seen = seen(g.cable, g.with, g.gap_mm, g.location);
  }
  for (SimDefect& d : sim.defects)
    if (d.kind == "clearance" || d.kind == "foreign_object")
      for (const SimGap& g : sim.gaps)  // the defect is one of the cable's gaps
        if (g.cable == d.element && g.location == d.location && g.gap_mm == d.gap_mm) d.seen = g.seen;
}

}  // namespace ewis::sim
