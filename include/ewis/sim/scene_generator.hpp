#pragma once
// Seeded generator of EWIS-like inspection scenes with ground truth (docs/sim.md): a base structure
// (plate, ribs, blocks), brackets, clamps and connectors, 0-2 rigid pipes and 1-3 cables along routes of
// straight runs, arcs and helices. The NOMINAL routes go into the CAD; the AS-BUILT routes (a few mm off,
// other bend radii) and any foreign object are what the sensor scans. Defects are injected on purpose and
// then read back from the as-built geometry, so the truth always matches what is built.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ewis/core/pose.hpp"
#include "ewis/io/plan_file.hpp"
#include "ewis/scene/scene.hpp"
#include "ewis/sim/route.hpp"
#include "ewis/sim/shapes.hpp"

namespace ewis::sim {

enum class DefectKind { None, Bend, Clearance, ForeignObject, Random };
// "none" | "bend" | "clearance" | "foreign_object" | "random"; nullopt otherwise.
std::optional<DefectKind> parse_defect_kind(const std::string& text);
const char* defect_kind_name(DefectKind kind);

// Margins that keep every check clear of its threshold (docs/sim.md "Margins").
struct SceneMargins {
  double clean_bend_factor = 1.2;      // clean: every bend radius >= 1.2 x allowed
  double clean_gap_mm = 2.0;           // clean: every gap >= clearance + 2 mm
  double defect_bend_factor = 0.85;    // defect: bend radius <= 0.85 x allowed
  double defect_gap_mm = 1.0;          // defect: gap <= clearance - 1 mm
};

struct SceneParams {
  std::uint64_t seed = 1;
  DefectKind defect = DefectKind::None;
  std::string clearance_with;  // for Clearance: "pipe", "bracket", "cable", or "" (any)
  int cables = 0;              // 1-3; 0: random
  int pipes = -1;              // 0-2; -1: random
  // Every cable's diameter drawn from [lo, hi] mm instead of the defaults (cable_A 4-14 or 4-30, cable_B 3-16,
  // cable_C 3 to A's + 6): e.g. single wires of 1.5-3 mm, 3-6 pixels across at the sensor's 0.5 mm spacing.
  std::optional<std::pair<double, double>> cable_diameter_mm;
  SensorModel sensor;
  double view_tilt_max_deg = 30.0;   // camera direction off the plate normal
  double standoff_tolerance_mm = 6.0;  // paper 5: 600 mm +- 6 mm
  SceneMargins margins;
  int max_attempts = 400;
};

struct SimCable {
  std::string name;
  double diameter_mm = 0.0;
  double allowed_bend_radius_mm = 0.0;
  bool rule_as_ratio = false;  // plan says min_bend_ratio (else min_bend_radius_mm)
  double bend_ratio = 0.0;     // allowed radius / diameter, as the plan writes it when rule_as_ratio
  double clearance_mm = 0.0;
  Route nominal;   // CAD
  Route as_built;  // scanned
  std::vector<std::string> attached;
};

struct SimRigid {
  std::string name;
  Solid solid;
  bool foreign = false;  // not in the CAD (a foreign object)
};

// Least surface-to-surface distance of an as-built cable to another element.
struct SimGap {
  std::string cable, with;
  bool with_foreign = false;
  double gap_mm = 0.0;
  Eigen::Vector3d location = Eigen::Vector3d::Zero();  // closest point on the cable's centreline
  // The gap's two ends: the closest points on the cable's surface and on the other element's surface.
  Eigen::Vector3d on_cable_surface = Eigen::Vector3d::Zero(), on_other_surface = Eigen::Vector3d::Zero();
  // With a scan: whether the sensor measured both surfaces at the gap's ends (gap_visibility.hpp).
  std::optional<bool> seen;
};

struct SimDefect {
  std::string kind;     // "bend" | "clearance" | "foreign_object"
  std::string element;  // the cable
  std::string with;     // clearance: the other element; empty otherwise
  double radius_mm = 0.0;  // bend
  double gap_mm = 0.0;     // clearance, foreign_object
  Eigen::Vector3d location = Eigen::Vector3d::Zero();
  // clearance, foreign_object: as SimGap's
  Eigen::Vector3d on_cable_surface = Eigen::Vector3d::Zero(), on_other_surface = Eigen::Vector3d::Zero();
  std::optional<bool> seen;
};

struct SimScene {
  std::uint64_t seed = 0;
  DefectKind requested = DefectKind::None;
  std::vector<SimCable> cables;
  std::vector<SimRigid> rigids;   // CAD rigid elements, then foreign objects
  std::vector<SimGap> gaps;       // every cable to every non-attached element (as built)
  std::vector<SimDefect> defects;
  SensorModel sensor;
  Pose camera_to_cad = Pose::Identity();  // the true sensor pose
  Eigen::Vector3d view_target = Eigen::Vector3d::Zero();
  int attempts = 0;
};

// Deterministic for a seed. Throws ewis::ProcessingError when no valid scene is found in max_attempts.
SimScene generate_scene(const SceneParams& params);

// Spacing of tube meshes and truth centrelines.
struct TubeMeshParams {
  double max_spacing_mm = 1.0;
  int segments = 48;
};
// The CAD (nominal cables, rigid elements; one element per name, no foreign objects).
Scene nominal_scene(const SimScene& sim, const TubeMeshParams& mesh = {});
// What the sensor sees: as-built cables, rigid elements and foreign objects.
Scene as_built_scene(const SimScene& sim, const TubeMeshParams& mesh = {});
// The plan.json content: sensor block and every element (cables with their rules and `attached`).
InspectionPlan scene_plan(const SimScene& sim);

// Recomputes gaps and defects from the as-built geometry (used by the generator and by tests).
void measure_scene(SimScene& sim);

}  // namespace ewis::sim
