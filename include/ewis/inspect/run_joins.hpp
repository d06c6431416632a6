#pragma once
// A bend hidden in the gap between two runs of one cable (see join_runs_across_gaps).
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "ewis/search/kdtree.hpp"
#include "ewis/tubes/trace.hpp"

namespace ewis {

struct RunJoinParams {
  bool enabled = true;
  // Two run ends this near each other (max(max_gap_diameters x diameter, min_gap_mm)) may hide a bend between them.
  double max_gap_diameters = 8.0;
  double min_gap_mm = 20.0;
  // Each run's part kept beside the gap (arc length from its end): room for a fillet's window and legs.
  double keep_diameters = 20.0;
  // The ends' outward directions (each over its last end_direction_diameters) must turn at least this much: a cable
  // going straight on under an occluder hides no bend.
  double end_direction_diameters = 2.0;
  double min_turn_deg = 5.0;
  // ... and their lines meet: they pass within max_miss_diameters x diameter of each other, ahead of both ends.
  double max_miss_diameters = 1.5;
  // The bend measured across the gap counts only where its place lies within max(near_gap_diameters x diameter,
  // near_gap_min_mm) of the gap (the straight line between the ends): elsewhere the runs measure it themselves.
  double near_gap_diameters = 2.0;
  double near_gap_min_mm = 10.0;
  // The fits across the gap judge their legs on their points wherever their windows lie
  // (FilletRefineParams::leg_drift_inside): a leg there may lie where nothing was traced.
  bool fillet_leg_drift_inside = true;
  // The occluder's edge: a structured-light sensor reports mixed pixels along its silhouette, at depths between it and
  // the cable behind, and some lie on the cable's surface band right at the gap's ends, where the fit on both sides
  // is most sensitive (a 27.5 mm bend under a crossing cable read 23.9-26.5 mm with them, 26.7-27.4 without). Scan
  // points within edge_reach_diameters x diameter of the gap (beyond half its length) with another scan point in
  // front of them (on their ray towards the sensor from front_min_mm to front_max_mm, within front_ray_mm of it)
  // are left out of the join's fit.
  bool drop_edge_points = true;
  double edge_reach_diameters = 3.0;
  double front_min_mm = 4.0;
  double front_max_mm = 120.0;
  double front_ray_mm = 1.0;
  // A fork (DESIGN "branching harnesses"): where a third run end of the cable lies within
  // max(fork_reach_diameters x diameter, fork_reach_min_mm) of the gap between two ends (the straight line between
  // them), the cable forks there, and no two of the three are joined: a trunk traced as two runs meeting a branch's
  // run at the fork read the turn from trunk into branch as a bend (a 7.2 mm harness with a branch of its diameter 20
  // deg off it: 12.3 mm). A bend hidden under an occluder leaves two ends there.
  double fork_reach_diameters = 1.5;
  double fork_reach_min_mm = 5.0;
};

// Two runs of a cable joined across the gap between their ends: `centerline` is run `first`'s part beside the gap
// (ending at the gap), the gap as a straight line, and run `second`'s part (starting at it); `points` are both runs'
// scan points nearest to those parts. The straight line over the gap is no measurement: a bend there counts only as a
// fit on the surface points on both sides (bend_refine's fillet), see pipeline.cpp.
struct RunJoin {
  std::size_t first = 0, second = 0;  // indices into the runs
  std::vector<Eigen::Vector3d> centerline;
  std::vector<std::uint32_t> points;  // sorted
  double radius_mm = 0.0;             // the two runs' radii, weighted by their point counts
  Eigen::Vector3d gap_start = Eigen::Vector3d::Zero(), gap_end = Eigen::Vector3d::Zero();
};

// The joins of a cable's runs: every pair of run ends within the gap limit of each other, neither ended by an
// attached element ("stop region": a clamp holds the cable there, and each side is measured on its own) nor a loop,
// whose outward directions turn by at least min_turn_deg and point at each other, and whose lines meet ahead of both
// ends (a corner; not a hairpin's two legs side by side). A run end that stopped at an occlusion by a crossing cable,
// right on a bend, leaves the bend's arc split between two runs: neither measures it alone (each window there lacks
// a leg). `cloud`: the points the runs index. Deterministic (pairs in run order).
std::vector<RunJoin> join_runs_across_gaps(const std::vector<TubeTrace>& runs, const std::vector<Eigen::Vector3f>& cloud,
                                           double diameter_mm, const RunJoinParams& params = {});

// Where the cable forks: the centre of each group of three run ends lying together (one within the fork reach,
// RunJoinParams::fork_*, of the line between the others; ends at attached elements and loops do not count, as for the
// joins), and the place where a run ends inside another run's tube at least a diameter from that run's ends (a branch
// traced up to the trunk it leaves). Forks within the joins' gap limit of one found before are not listed again.
// Deterministic.
std::vector<Eigen::Vector3d> run_forks(const std::vector<TubeTrace>& runs, double diameter_mm,
                                       const RunJoinParams& params = {});

// The scan points within reach of the join's gap that something hides in part (see RunJoinParams::front_*): indices
// into `cloud`, increasing. `sensor`: the sensor's position in the cloud's frame. Only points `usable` allows (when
// given) are tested.
std::vector<std::uint32_t> points_under_something(const RunJoin& join, const std::vector<Eigen::Vector3f>& cloud,
                                                  const KdTree& tree, const std::vector<std::uint8_t>* usable,
                                                  const Eigen::Vector3d& sensor, double diameter_mm,
                                                  const RunJoinParams& params = {});

}  // namespace ewis
