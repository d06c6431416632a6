// Meshes and plan of a generated scene: the CAD (nominal) and what the sensor sees (as built + foreign).
#include <algorithm>

#include "ewis/sim/scene_generator.hpp"

namespace ewis::sim {

namespace {

Mesh tube_mesh(const Route& route, double radius, const TubeMeshParams& p) {
  const double spacing = std::min(p.max_spacing_mm, std::max(0.25, 0.5 * radius));
  return make_tube(sample_route(route, spacing), radius, p.segments);
}

void add(Scene& scene, const std::string& name, const Mesh& m) { add_element(scene, name, m.vertices, m.triangles); }

Scene build(const SimScene& sim, const TubeMeshParams& p, bool as_built) {
  Scene scene;
  for (const auto& r : sim.rigids)
    if (!r.foreign) add(scene, r.name, r.solid.mesh());
  for (const auto& c : sim.cables) add(scene, c.name, tube_mesh(as_built ? c.as_built : c.nominal, 0.5 * c.diameter_mm, p));
  if (as_built)
    for (const auto& r : sim.rigids)
      if (r.foreign) add(scene, r.name, r.solid.mesh());
  return scene;
}

}  // namespace

Scene nominal_scene(const SimScene& sim, const TubeMeshParams& mesh) { return build(sim, mesh, false); }
Scene as_built_scene(const SimScene& sim, const TubeMeshParams& mesh) { return build(sim, mesh, true); }

InspectionPlan scene_plan(const SimScene& sim) {
  InspectionPlan plan;
  plan.sensor = sim.sensor;
  for (const auto& c : sim.cables) {
    PlanElement e;
    e.name = c.name;
    e.kind = ElementKind::Cable;
    e.diameter_mm = c.diameter_mm;
    if (c.rule_as_ratio)
      e.min_bend_ratio = c.bend_ratio;
    else
      e.min_bend_radius_mm = c.allowed_bend_radius_mm;
    e.clearance_mm = c.clearance_mm;
    e.attached = c.attached;
    plan.elements.push_back(e);
  }
  for (const auto& r : sim.rigids)
    if (!r.foreign) {
      PlanElement e;
      e.name = r.name;
      e.kind = ElementKind::Rigid;
      plan.elements.push_back(e);
    }
  return plan;
}

}  // namespace ewis::sim
