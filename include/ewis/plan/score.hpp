#pragma once
// The scoring function of paper 3.3: the number of pixels of the element in an element-id render of the whole
// CAD scene from the candidate (occlusion by every other element counts), plus two things beyond the paper:
// a "measurable" score (only pixels the structured-light sensor can measure) and the rejection of candidates
// that collide with the assembly.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "ewis/core/camera.hpp"
#include "ewis/core/pose.hpp"
#include "ewis/core/progress.hpp"
#include "ewis/plan/candidates.hpp"
#include "ewis/raycast/raycaster.hpp"

namespace ewis {

// A structured-light sensor: a pixel is measurable when the camera sees the point, the projector (offset by
// baseline_mm along the camera's +x axis) lights it, and both rays meet the surface at incidence angles
// (from the surface normal) below max_incidence_deg.
struct MeasurableModel {
  double baseline_mm = 100.0;
  double max_incidence_deg = 75.0;
};

struct ScoreParams {
  bool measurable = false;      // score measurable pixels instead of visible pixels
  MeasurableModel sensor;
  // A candidate is rejected (score 0) when any CAD geometry is closer than this to the sensor position,
  // or when the sensor position is inside a closed element. Negative: half the candidate sphere's radius.
  double min_distance_mm = -1.0;
};

struct CandidateScore {
  std::uint64_t score_px = 0;     // pixels of the element in the render of the whole scene
  // Filled by add_visible_fractions (only where asked: it costs a second render).
  std::uint64_t isolated_px = 0;  // the same with every other element removed
  double visible_fraction = 0.0;  // score_px / isolated_px (0 when isolated_px is 0)
  bool rejected = false;
  std::string reject_reason;      // "inside geometry" or "geometry within N mm"
};

// Image window of the element's bounding box seen from `camera_to_cad` (the whole image when a corner is
// behind the camera); an empty window (col0 >= col1 or row0 >= row1) when the box is outside the image.
PixelWindow projected_window(const Camera& camera, const Pose& camera_to_cad, const Element& element);

// Pixels (row * width + col, increasing) whose centre lies in the projection of some triangle of `element`
// (with a 0.01 px margin): the only pixels that can show it. False when part of the element is at or behind
// the camera plane (then no footprint is given).
bool element_footprint(const Scene& scene, const Camera& camera, const Pose& camera_to_cad, std::uint32_t element,
                       std::vector<std::uint32_t>& pixels);

// Paper 3.3's score: pixels showing `element` in the element-id render of `caster` (the same count as
// count_element_pixels), casting only the rays of the element's footprint.
std::uint64_t count_visible_pixels(const Raycaster& caster, const Camera& camera, const Pose& camera_to_cad,
                                   std::uint32_t element);

// Pixels of `element` the sensor can measure (see MeasurableModel): footprint rays, then shadow rays.
std::uint64_t count_measurable_pixels(const Raycaster& caster, const Camera& camera, const Pose& camera_to_cad,
                                      std::uint32_t element, const MeasurableModel& model);

// Why a sensor at `position` is impossible: "" when it is fine. Inside: most of six axis rays from the
// position first meet the back (inner) side of a triangle (outward winding). Near: some triangle closer than
// min_distance_mm.
std::string sensor_position_problem(const Scene& scene, const Raycaster& scene_caster,
                                    const Eigen::Vector3d& position, double min_distance_mm);

// Scores every candidate, in parallel (results do not depend on the thread count); `scene_caster` holds the
// whole scene. `radius_mm` is the candidate sphere's radius (for the default min distance). Progress may be
// reported from worker threads. isolated_px and visible_fraction stay 0: see add_visible_fractions.
std::vector<CandidateScore> score_candidates(const Raycaster& scene_caster, const Camera& camera,
                                             std::uint32_t element, const std::vector<Candidate>& candidates,
                                             double radius_mm, const ScoreParams& params,
                                             const ProgressFn& progress = {});

// Fills isolated_px and visible_fraction of scores[i] for each i in `which` (all when empty), from
// `element_caster`, a ray caster holding only `element` (same Scene). Parallel, thread-count independent.
void add_visible_fractions(const Raycaster& element_caster, const Camera& camera, std::uint32_t element,
                           const std::vector<Candidate>& candidates, const ScoreParams& params,
                           std::vector<CandidateScore>& scores, const std::vector<std::size_t>& which = {});

}  // namespace ewis
