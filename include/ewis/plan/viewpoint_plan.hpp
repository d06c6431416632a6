#pragma once
// `ewis plan` as a library call (paper 3): candidates around each listed element, scores, the best views,
// and (for several elements) a small viewpoint set covering them all; then viewpoints.json and pictures.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "ewis/core/camera.hpp"
#include "ewis/core/progress.hpp"
#include "ewis/io/plan_file.hpp"
#include "ewis/plan/candidates.hpp"
#include "ewis/plan/coverage.hpp"
#include "ewis/plan/score.hpp"
#include "ewis/scene/scene.hpp"

namespace ewis {

struct ViewpointParams {
  CandidateParams candidates;  // radius_mm <= 0: the sensor's standoff_mm
  ScoreParams score;
  std::size_t top = 5;         // length of each `best` list
  CoverageParams coverage;
  bool force_coverage = false;  // also compute a coverage set for a single element
};

struct ElementViewpoints {
  std::string name;
  std::uint32_t element = 0;        // index in the Scene
  CandidateGrid grid;               // candidates around its centre of mass
  std::vector<CandidateScore> scores;
  std::vector<std::size_t> best;    // candidate indices: score_px descending, ties in candidate order
};

struct CoverageViewpoint {
  std::size_t sphere = 0;     // index into ViewpointPlan::elements: whose candidate sphere
  std::size_t candidate = 0;  // index into that sphere's candidates
  std::vector<double> gained;  // per listed element, fraction of its area this view adds
};

struct CoverageSet {
  double target_fraction = 0.9;
  std::vector<CoverageViewpoint> viewpoints;  // greedy order
  std::vector<double> coverage;               // per listed element
  std::vector<double> best_single;            // per listed element
  std::vector<double> reachable;              // per listed element: seen by any candidate
  bool complete = false;
  std::size_t lower_bound = 0;
  double greedy_factor = 1.0;
  std::size_t samples_per_element = 0;
};

struct ViewpointPlan {
  SensorModel sensor;
  ViewpointParams params;            // as used (radius resolved)
  std::vector<ElementViewpoints> elements;
  // The top-level `best`: (sphere, candidate) pairs, score_px descending over all spheres, ties in order.
  std::vector<std::pair<std::size_t, std::size_t>> best;
  bool has_coverage = false;
  CoverageSet coverage;
};

// Element indices for the names given to --element: each name must be a CAD element; "all-cables" stands for
// every cable of the plan, in plan order. Duplicates are dropped (first kept). Throws InputError(cad_path, ...)
// naming an unknown element, and InputError(plan_path, ...) when "all-cables" finds no cable.
std::vector<std::uint32_t> resolve_elements(const Scene& scene, const InspectionPlan& plan,
                                            const std::vector<std::string>& names, const std::string& cad_path,
                                            const std::string& plan_path);

// Runs the whole selection. Deterministic and independent of the thread count.
ViewpointPlan plan_viewpoints(const Scene& scene, const SensorModel& sensor,
                              const std::vector<std::uint32_t>& elements, const ViewpointParams& params,
                              const ProgressFn& progress = {});

// viewpoints.json of CONTRACT.md (plus extra fields; see docs/plan.md), pretty-printed, byte-stable.
std::string viewpoints_json(const ViewpointPlan& plan);

// Writes DIR/view_K.png (best views), DIR/cover_K.png (coverage set), DIR/heatmap.png (first element) and
// DIR/heatmap_<name>.png (each element, when several), then DIR/viewpoints.json; every file atomically.
// `dir` must exist.
void write_viewpoint_outputs(const Scene& scene, const ViewpointPlan& plan, const std::string& dir,
                             const ProgressFn& progress = {});

}  // namespace ewis
