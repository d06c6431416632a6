#pragma once
// The inspection plan of CONTRACT.md ("Inspection plan (--plan FILE, JSON)").
#include <optional>
#include <string>
#include <vector>

#include "ewis/core/camera.hpp"

namespace ewis {

struct SensorModel {
  int width_px = 1280;
  int height_px = 1024;
  double hfov_deg = 58.0;
  double standoff_mm = 600.0;
  Camera camera() const { return {width_px, height_px, hfov_deg}; }
};

enum class ElementKind { Cable, Rigid };
enum class BendReference { Centreline, Inner };

struct PlanElement {
  std::string name;
  ElementKind kind = ElementKind::Rigid;
  double diameter_mm = 0.0;                   // cables only, > 0
  std::optional<double> min_bend_radius_mm;   // one of these two for a cable
  std::optional<double> min_bend_ratio;       // allowed radius = ratio * diameter
  double clearance_mm = 0.0;                  // least allowed surface-to-surface gap
  BendReference bend_reference = BendReference::Centreline;
  std::vector<std::string> attached;          // elements touching it by design

  // The allowed bend radius in mm (from min_bend_radius_mm or ratio x diameter); 0 when no rule.
  double allowed_bend_radius_mm() const {
    if (min_bend_radius_mm) return *min_bend_radius_mm;
    if (min_bend_ratio) return *min_bend_ratio * diameter_mm;
    return 0.0;
  }
};

struct InspectionPlan {
  SensorModel sensor;
  std::vector<PlanElement> elements;

  const PlanElement* find(const std::string& name) const {
    for (const auto& e : elements)
      if (e.name == name) return &e;
    return nullptr;
  }
};

// Throws InputError(path, what) on a missing/malformed file or a plan that contradicts itself
// (duplicate names, a cable without a positive diameter, negative clearance, both or neither bend rule...).
InspectionPlan read_plan(const std::string& path);
InspectionPlan parse_plan(const std::string& json_text, const std::string& path_for_errors);
std::string plan_to_json(const InspectionPlan& plan);  // pretty JSON text, parses back to the same plan

}  // namespace ewis
