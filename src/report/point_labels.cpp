// Per-point labels of the inspected scan: which cable, which interference cluster, or the rest.
#include <algorithm>

#include "ewis/report/pictures.hpp"

namespace ewis {

Rgb interference_color(bool foreign) { return foreign ? Rgb{230, 20, 20} : Rgb{255, 140, 0}; }

PointLabels label_points(const InspectionResult& r) {
  const std::size_t n = r.cloud.size();
  PointLabels l;
  l.kind.assign(n, PointKind::Rest);
  l.cable.assign(n, -1);
  l.foreign.assign(n, 0);
  for (std::size_t k = 0; k < r.cables.size(); ++k) {
    if (!r.cables[k].found) continue;
    for (std::uint32_t i : r.cables[k].trace.points)
      if (i < n) {
        l.kind[i] = PointKind::Cable;
        l.cable[i] = static_cast<std::int16_t>(std::min<std::size_t>(k, 32767));
      }
  }
  // Interference clusters come after all cables so a point claimed by another cable stays that cable's
  // (the same rule as result_clouds of the inspect stage).
  for (std::size_t k = 0; k < r.cables.size(); ++k)
    for (const Interference& f : r.cables[k].interferences)
      for (std::uint32_t i : f.points)
        if (i < n && l.kind[i] != PointKind::Cable) {
          l.kind[i] = PointKind::Interference;
          l.cable[i] = static_cast<std::int16_t>(std::min<std::size_t>(k, 32767));
          l.foreign[i] = f.with ? 0 : 1;
        }
  return l;
}

}  // namespace ewis
