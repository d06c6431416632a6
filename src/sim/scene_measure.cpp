// Gaps and defects read back from the as-built geometry (the truth is what is built, not what was meant).
#include <algorithm>
#include <cmath>

#include "ewis/sim/scene_generator.hpp"

namespace ewis::sim {

std::optional<DefectKind> parse_defect_kind(const std::string& text) {
  if (text == "none") return DefectKind::None;
  if (text == "bend") return DefectKind::Bend;
  if (text == "clearance") return DefectKind::Clearance;
  if (text == "foreign_object") return DefectKind::ForeignObject;
  if (text == "random") return DefectKind::Random;
  return std::nullopt;
}

const char* defect_kind_name(DefectKind kind) {
  switch (kind) {
    case DefectKind::None: return "none";
    case DefectKind::Bend: return "bend";
    case DefectKind::Clearance: return "clearance";
    case DefectKind::ForeignObject: return "foreign_object";
    case DefectKind::Random: return "random";
  }
  return "none";
}

namespace {

// The point of `solid`'s surface nearest to p (outside it): p moved by its distance against the distance's gradient
// (central differences). p itself when it lies on or inside the solid.
Eigen::Vector3d closest_on_solid(const Solid& solid, const Eigen::Vector3d& p) {
  const double d = solid.distance(p);
  if (!(d > 1e-9)) return p;
  constexpr double h = 1e-4;
  Eigen::Vector3d grad;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(k);
    grad[k] = (solid.distance(p + e) - solid.distance(p - e)) / (2.0 * h);
  }
  return grad.norm() > 1e-12 ? Eigen::Vector3d(p - d * grad.normalized()) : p;
}

// A point at `radius` from the centreline point c towards `towards` (c itself when they coincide).
Eigen::Vector3d towards(const Eigen::Vector3d& c, const Eigen::Vector3d& target, double radius) {
  const Eigen::Vector3d v = target - c;
  return v.norm() > 1e-12 ? Eigen::Vector3d(c + radius * v.normalized()) : c;
}

}  // namespace

void measure_scene(SimScene& sim) {
  sim.gaps.clear();
  sim.defects.clear();
  const std::size_t nc = sim.cables.size();
  // Cable pairs once, used from both sides.
  std::vector<std::vector<GapResult>> pair(nc, std::vector<GapResult>(nc));
  for (std::size_t i = 0; i < nc; ++i)
    for (std::size_t j = i + 1; j < nc; ++j) {
      const Tube a{&sim.cables[i].as_built, 0.5 * sim.cables[i].diameter_mm};
      const Tube b{&sim.cables[j].as_built, 0.5 * sim.cables[j].diameter_mm};
      pair[i][j] = tube_tube_gap(a, b);
      pair[j][i] = pair[i][j];
      pair[j][i].on_cable = pair[i][j].on_other;
      pair[j][i].on_other = pair[i][j].on_cable;
    }
  for (std::size_t i = 0; i < nc; ++i) {
    const SimCable& c = sim.cables[i];
    const double r_min = c.as_built.min_curvature_radius_mm();
    if (std::isfinite(r_min) && r_min < c.allowed_bend_radius_mm) {
      SimDefect d;
      d.kind = "bend";
      d.element = c.name;
      d.radius_mm = r_min;
      d.location = c.as_built.at(c.as_built.min_curvature_location_s());
      sim.defects.push_back(d);
    }
    const auto attached = [&](const std::string& n) {
      return std::find(c.attached.begin(), c.attached.end(), n) != c.attached.end();
    };
    // `other_surface`: the other element's closest surface point
    const auto add_gap = [&](const std::string& with, bool foreign, const GapResult& g,
                             const Eigen::Vector3d& other_surface) {
      SimGap gap;
      gap.cable = c.name;
      gap.with = with;
      gap.with_foreign = foreign;
      gap.gap_mm = g.gap_mm;
      gap.location = g.on_cable;
      gap.on_cable_surface = towards(g.on_cable, other_surface, 0.5 * c.diameter_mm);
      gap.on_other_surface = other_surface;
      sim.gaps.push_back(gap);
      if (g.gap_mm < c.clearance_mm) {
        SimDefect d;
        d.kind = foreign ? "foreign_object" : "clearance";
        d.element = c.name;
        d.with = foreign ? "" : with;
        d.gap_mm = g.gap_mm;
        d.location = g.on_cable;
        d.on_cable_surface = gap.on_cable_surface;
        d.on_other_surface = gap.on_other_surface;
        sim.defects.push_back(d);
      }
    };
    for (std::size_t j = 0; j < nc; ++j)
      if (j != i && !attached(sim.cables[j].name)) {
        const GapResult& g = pair[i][j];
        add_gap(sim.cables[j].name, false, g, towards(g.on_other, g.on_cable, 0.5 * sim.cables[j].diameter_mm));
      }
    const Tube tube{&c.as_built, 0.5 * c.diameter_mm};
    for (const SimRigid& r : sim.rigids)
      if (!attached(r.name)) {
        const GapResult g = tube_solid_gap(tube, r.solid);
        add_gap(r.name, r.foreign, g, closest_on_solid(r.solid, g.on_cable));
      }
  }
}

}  // namespace ewis::sim
