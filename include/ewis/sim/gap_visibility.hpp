#pragma once
// Whether a scan shows both surfaces of a gap (issue 6's goal: "interference gap within 0.5 mm of the truth where
// both surfaces are seen"). Seen: the sensor measured (at least min_points surface points of each element; outliers,
// mixed pixels and mismatch patches do not count)
//  - the cable around the gap: its points within cable_reach_mm beyond its radius of the gap's centreline point (a
//    cable is measured as a tube fitted to what is seen of it, so its flank facing the gap need not be seen), and
//  - the other element's surface where it comes within other_within_mm of the gap: its points no farther than
//    gap + other_within_mm from the cable's surface (a box's edge along the cable has a line of closest points).
// The contact of an object lying under or against a cable seen from above is hidden, as are the facing flanks of
// two cables side by side: such a gap is read from the models (a rigid element's CAD) or bounded (a foreign
// object's seen points: an upper bound) and is not "seen".
#include <cstddef>

#include "ewis/core/pose.hpp"
#include "ewis/scene/scene.hpp"
#include "ewis/sim/scene_generator.hpp"
#include "ewis/sim/sensor.hpp"

namespace ewis::sim {

struct GapSeenParams {
  double cable_reach_mm = 1.5;    // a tube section 2 sqrt(3 r + 2.25) mm long: 8.3 mm for a 5 mm radius
  double other_within_mm = 0.5;   // the goal's tolerance
  std::size_t min_points = 3;
  double max_gap_over_clearance_mm = 5.0;  // gaps wider than the cable's clearance by more are not looked at
};

// Sets `seen` of every gap up to max_gap_over_clearance_mm over its cable's clearance and of every clearance /
// foreign-object defect of `sim` from `scan` (in the sensor's frame, camera_to_cad its pose) of `built` (the as-built
// scene the scan was taken of: its element names are the cables' and the rigid elements' names).
void mark_seen_gaps(SimScene& sim, const Scene& built, const ScanResult& scan, const Pose& camera_to_cad,
                    const GapSeenParams& params = {});

}  // namespace ewis::sim
