#pragma once
// Clumps standing off a cable's surface by a step: a structured-light sensor's matching errors (a few pixels on a
// shiny spot given one wrong depth: `ewis simulate --mismatch-patches`) are dense patches moved along their rays, which
// radius outlier removal keeps; those in or near the cable's tube lie where its bend fits look. Robust fits weigh such
// a patch down but not out: a quartic tube bent towards a 32-point patch 1.4 mm deep in a 3.7 mm cable and read a
// 49.7 mm bend as 18.5 mm. The bend fits (bend_refine) therefore leave them out.
//
// A clump here: points whose offset from the tube (distance to the measured centreline less the tube radius, less the
// median offset of all the points given) exceeds max(min_offset_sigmas x their robust sigma, min_offset_mm), linked
// within link_resolutions x the scan resolution, all off to the same side. It is a step, not a trend, when the points
// around it (those within ring_resolutions x resolution of a clump point across that point's ray: its neighbours in
// the sensor's image) lie off the tube by at least min_step_fraction of the clump's offset less (and at least by the
// threshold): a patch's neighbours lie on the surface, while the points around a tight bend's apex, where the
// centreline cuts the corner, lie off it nearly as far as the apex's own (the offset grows smoothly), so a real
// bend's surface is not left out. Another object's surface beside the cable (a clamp, a touching neighbour) may be
// found too: it is no part of the cable's surface either.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace ewis {

struct SurfaceClumpParams {
  bool enabled = true;
  double min_offset_sigmas = 5.0;    // off the tube by this many robust sigmas of the offsets ...
  double min_offset_mm = 0.5;        // ... and at least this much
  double min_noise_mm = 0.05;        // floor of that sigma (noise-free scans)
  double link_resolutions = 2.0;     // clump points link within this x the scan resolution
  double ring_resolutions = 2.0;     // the clump's neighbours: within this x resolution across the rays
  double min_step_fraction = 0.5;    // the step at the clump's edge, as a fraction of its median offset
  std::size_t min_points = 3;        // smaller clumps are single stray points: the fits' robust loss handles them
  std::size_t min_ring_points = 3;   // a clump with fewer neighbours has no edge to judge by (kept)
  // A clump found grows over the points linked to it that lie off to its side by grow_fraction of its median offset and
  // grow_min_sigmas robust sigmas: the patch's rim, where its rays meet the tube aslant and the move shows less across
  // the surface.
  double grow_fraction = 0.5;
  double grow_min_sigmas = 3.0;
  // inspect: the points looked at are the usable scan points within the run's tube radius + max(margin_mm, margin_radii
  // x radius) of its centreline (a patch moved into the tube lies off the trace's band but in the fits' way)
  double margin_mm = 1.0;
  double margin_radii = 0.5;
};

struct SurfaceClumps {
  std::vector<std::uint32_t> points;  // indices into the points given, increasing
  std::size_t clumps = 0;
  double sigma_mm = 0.0;              // the robust sigma of the offsets
};

// `points`: the points in and around a cable's tube; `centerline`: its measured centreline (ordered, >= 2 points),
// `tube_radius_mm` its radius; `sensor`: the sensor's position (same frame). Deterministic.
SurfaceClumps surface_step_clumps(const std::vector<Eigen::Vector3d>& points,
                                  const std::vector<Eigen::Vector3d>& centerline, double tube_radius_mm,
                                  const Eigen::Vector3d& sensor, double resolution_mm,
                                  const SurfaceClumpParams& params = {});

}  // namespace ewis
