#pragma once
// The registration target built from the CAD (paper 4.1.1-4.2): area-weighted samples of the RIGID elements
// only, with their triangle normals. Cables are flexible and move (paper 4.2), so they never anchor the pose:
// the cable elements are sampled too, but only to mark an exclusion zone around their CAD position.
//
// Rule: a scan point (in CAD coordinates, at the current pose estimate) is left out of the registration when it
// lies within `cable_margin_mm` + the sampling spacing of a cable's sampled CAD surface, i.e. within
// radius + margin of the cable's CAD centreline. Points of a cable that moved farther than that find no rigid
// surface within the final correspondence distance (or are down-weighted by the robust kernel).
#include <cstdint>
#include <memory>
#include <vector>

#include "ewis/core/cloud.hpp"
#include "ewis/core/pose.hpp"
#include "ewis/io/plan_file.hpp"
#include "ewis/scene/scene.hpp"
#include "ewis/scene/surface_index.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis {

struct CadTargetParams {
  double spacing_mm = 1.0;          // sample spacing (about the scan resolution)
  std::size_t max_points = 2000000; // cap on the rigid samples (0: none)
  std::uint64_t seed = 1;
  double cable_margin_mm = 3.0;     // exclusion zone around a cable's CAD surface
  // false: `rigid` stays empty and each registration pass draws the same samples again keeping only those it
  // looks at (sample_rigid_view), so the whole CAD's samples never sit in memory (issue 8: inspect's peak memory).
  // The target then references the scene, which must outlive it.
  bool sample_up_front = true;
  // true: the target also indexes the rigid elements' triangles (SurfaceIndex) for the registration's last step on
  // the exact surface (surface_refine.hpp). The target then references the scene, which must outlive it.
  bool exact_surface = false;
};

// Owns the sampled clouds and the cables' k-d tree (it references `cables`: not copyable). The rigid samples
// get no tree here: each registration pass builds one over the cropped view it uses (scan_to_cad.cpp), and
// only the global search builds one over all of them (a whole-CAD tree was ~25 MB of inspect's peak).
struct CadTarget {
  Cloud rigid;                               // rigid samples with triangle normals (empty when sampled per view)
  std::vector<std::uint32_t> rigid_element;  // element index per rigid sample
  const Scene* scene = nullptr;              // set when sampled per view
  std::vector<int> rigid_elements;           // the anchoring elements
  std::size_t max_points = 0;
  std::uint64_t seed = 1;
  // the rigid triangles (CadTargetParams::exact_surface), or null; shared: inspect keeps it for its rigid labels and
  // gaps after the target is gone
  std::shared_ptr<const SurfaceIndex> surface;
  Cloud cables;                              // cable samples (exclusion zone only)
  std::unique_ptr<KdTree> cable_tree;        // null when the plan has no cable in the scene
  double spacing_mm = 1.0;
  double cable_margin_mm = 3.0;
};

// Elements the plan lists as cables are excluded from the anchor set; everything else (listed rigid or not
// listed) anchors. Throws InputError when the scene has no rigid triangle at all.
CadTarget build_cad_target(const Scene& scene, const InspectionPlan& plan, const CadTargetParams& params = {});

// Whether the target has rigid samples or can draw them per view.
bool has_rigid(const CadTarget& target);

// The rigid samples inside the box [lo, hi] and, when `eye` is given, facing it (normal at most ~100 deg from
// the direction to the eye: grazing walls stay, far sides go). From the up-front samples, or else drawn now
// from the scene (the same samples as up front, of which only the view is kept).
Cloud sample_rigid_view(const CadTarget& target, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi,
                        const Eigen::Vector3d* eye);

// The cable samples inside the box [lo, hi] and, when `eye` is given, facing it (as sample_rigid_view).
Cloud sample_cable_view(const CadTarget& target, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi,
                        const Eigen::Vector3d* eye);

// Every rigid sample: the up-front ones, or drawn now.
Cloud sample_rigid_all(const CadTarget& target);

// Indices (increasing) of `source` points that, mapped by source_to_cad, are farther than
// target.cable_margin_mm + extra_margin_mm + target.spacing_mm from every cable sample: the points allowed to
// pull the pose. All points when the target has no cables.
std::vector<std::uint32_t> points_away_from_cables(const std::vector<Eigen::Vector3f>& source,
                                                   const Pose& source_to_cad, const CadTarget& target,
                                                   double extra_margin_mm = 0.0);

}  // namespace ewis
