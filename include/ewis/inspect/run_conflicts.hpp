#pragma once
// Two cables' traces on the same scan points: which one the place belongs to (see drop_runs_on_other_cables).
#include <cstddef>
#include <vector>

#include "ewis/inspect/pipeline.hpp"
#include "ewis/scene/scene.hpp"

namespace ewis {

// A run of cable `cable` that lies on run `other_run` of cable `other_cable`, whose place it is (see below).
struct RunOnOtherCable {
  std::size_t cable = 0, run = 0;
  std::size_t other_cable = 0, other_run = 0;
};

// The runs drop_runs_on_other_cables drops, each with the run whose place it is, without editing anything (in the
// order of the pairs of runs: deterministic). A run may appear more than once.
std::vector<RunOnOtherCable> runs_on_other_cables(const std::vector<CableInspection>& cables, const Scene& scene,
                                                  const std::vector<Eigen::Vector3f>& cloud,
                                                  double max_shared_fraction = 0.5);

// A run of one cable that shares more than `max_shared_fraction` of its points (or of the other run's, whichever
// is smaller) with a run of another cable, or whose axis lies inside the other run's tube (within the larger radius
// plus half the smaller) at more than that share of its sub-cables' ends, lies on one of the two cables only. When
// the plan's diameters differ by more than 5 %, the place belongs to the cable whose gauge the two runs' mean fitted
// radius is nearer (in log): the gauges as the two cables' other runs measure them (the median of their sub-cables'
// radii, at least 8 of them each) when both have such runs and the two differ as the plan's do, by at least half as
// much; else the plan radii. Otherwise it belongs to the cable whose registered CAD surface lies nearer to the shared
// stretch (mean over the two runs' scan points). The other cable's run is dropped. Why: a run after the first starts
// from the CAD samples earlier runs left uncovered; where the cable's own points there are out of reach (beside a
// bracket it touches) and its CAD lies off its as-built course toward a neighbour, the run can start on the
// neighbour and walk along it. `cables[c].runs` are edited in place (the merged `trace` is not). `cloud`: the scan
// points the runs index. Returns the number of runs dropped. Deterministic.
std::size_t drop_runs_on_other_cables(std::vector<CableInspection>& cables, const Scene& scene,
                                      const std::vector<Eigen::Vector3f>& cloud, double max_shared_fraction = 0.5);

}  // namespace ewis
