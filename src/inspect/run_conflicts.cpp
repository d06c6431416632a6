// Runs of two cables on the same scan points (see run_conflicts.hpp).
#include "ewis/inspect/run_conflicts.hpp"

#include <algorithm>
#include <cstdint>
#include <map>
#include <memory>
#include <utility>

#include "ewis/scene/surface_index.hpp"

namespace ewis {
namespace {

struct RunRef {
  std::size_t cable = 0, run = 0;
};

// Mean distance of the run's axis points (segment ends) to the CAD surface of `index`.
double mean_cad_distance(const TubeTrace& run, const SurfaceIndex& index) {
  double sum = 0;
  std::size_t n = 0;
  for (const SubCable& s : run.segments)
    for (const Eigen::Vector3d& p : {s.cylinder.start, s.cylinder.end}) {
      const SurfacePoint q = index.closest(p);
      if (!q.found()) continue;
      sum += q.distance_mm;
      ++n;
    }
  return n ? sum / double(n) : std::numeric_limits<double>::infinity();
}

}  // namespace

std::size_t drop_runs_on_other_cables(std::vector<CableInspection>& cables, const Scene& scene, std::size_t cloud_size,
                                      double max_shared_fraction) {
  std::vector<RunRef> refs;
  for (std::size_t c = 0; c < cables.size(); ++c)
    for (std::size_t k = 0; k < cables[c].runs.size(); ++k) refs.push_back({c, k});
  if (refs.size() < 2 || refs.size() >= UINT32_MAX) return 0;
  // Every (point, run) claim, sorted by point (memory of the runs' points, not of the scan): a point's first run
  // (in cable, run order) is its claimer, and each later run of another cable shares that point with it.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> claims;
  for (std::uint32_t r = 0; r < refs.size(); ++r)
    for (std::uint32_t i : cables[refs[r].cable].runs[refs[r].run].points)
      if (i < cloud_size) claims.emplace_back(i, r);
  std::sort(claims.begin(), claims.end());
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::size_t> shared;  // (earlier, later) run -> points
  for (std::size_t a = 0; a < claims.size();) {
    std::size_t b = a + 1;
    while (b < claims.size() && claims[b].first == claims[a].first) ++b;
    const std::uint32_t owner = claims[a].second;
    for (std::size_t k = a + 1; k < b; ++k)
      if (refs[claims[k].second].cable != refs[owner].cable) ++shared[{owner, claims[k].second}];
    a = b;
  }
  std::vector<std::unique_ptr<SurfaceIndex>> cad(cables.size());
  auto cad_of = [&](std::size_t c) -> const SurfaceIndex& {
    if (!cad[c]) cad[c] = std::make_unique<SurfaceIndex>(scene, std::vector<int>{cables[c].element});
    return *cad[c];
  };
  std::vector<std::uint8_t> drop(refs.size(), 0);
  for (const auto& [pair, count] : shared) {
    const RunRef& a = refs[pair.first];
    const RunRef& b = refs[pair.second];
    const TubeTrace& ra = cables[a.cable].runs[a.run];
    const TubeTrace& rb = cables[b.cable].runs[b.run];
    const std::size_t smaller = std::min(ra.points.size(), rb.points.size());
    if (double(count) <= max_shared_fraction * double(smaller)) continue;
    if (cables[a.cable].element < 0 || cables[b.cable].element < 0) continue;
    // the shared stretch is where both runs lie: judge each run's place against both CADs
    const double a_own = mean_cad_distance(ra, cad_of(a.cable)) + mean_cad_distance(rb, cad_of(a.cable));
    const double b_own = mean_cad_distance(ra, cad_of(b.cable)) + mean_cad_distance(rb, cad_of(b.cable));
    drop[a_own <= b_own ? pair.second : pair.first] = 1;
  }
  std::size_t dropped = 0;
  for (std::size_t r = refs.size(); r-- > 0;)
    if (drop[r]) {
      std::vector<TubeTrace>& runs = cables[refs[r].cable].runs;
      runs.erase(runs.begin() + std::ptrdiff_t(refs[r].run));
      ++dropped;
    }
  return dropped;
}

}  // namespace ewis
