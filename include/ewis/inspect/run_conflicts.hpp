#pragma once
// Two cables' traces on the same scan points: which one the place belongs to (see drop_runs_on_other_cables).
#include <cstddef>
#include <vector>

#include "ewis/inspect/pipeline.hpp"
#include "ewis/scene/scene.hpp"

namespace ewis {

// A run of one cable that shares more than `max_shared_fraction` of its points (or of the other run's, whichever
// is smaller) with a run of another cable lies on one of the two cables only. The place belongs to the cable whose
// registered CAD surface lies nearer to the shared stretch (mean over the runs' axis points), and the other
// cable's run is dropped. Why: a run after the first starts from the CAD samples earlier runs left uncovered;
// where the cable's own points there are out of reach (beside a bracket it touches) and its CAD lies off its
// as-built course toward a neighbour, the run can start on the neighbour and walk along it. `cables[c].runs` are
// edited in place (the merged `trace` is not). `cloud_size`: number of scan points the runs index. Returns the
// number of runs dropped. Deterministic.
std::size_t drop_runs_on_other_cables(std::vector<CableInspection>& cables, const Scene& scene, std::size_t cloud_size,
                                      double max_shared_fraction = 0.5);

}  // namespace ewis
