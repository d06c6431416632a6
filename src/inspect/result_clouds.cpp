#include <array>

#include "ewis/inspect/pipeline.hpp"

namespace ewis {

Rgb cable_color(std::size_t index) {
  static const std::array<Rgb, 8> palette = {{{31, 119, 180}, {44, 160, 44}, {148, 103, 189}, {23, 190, 207},
                                              {188, 189, 34}, {227, 119, 194}, {140, 86, 75}, {127, 127, 255}}};
  return palette[index % palette.size()];
}

ResultClouds result_clouds(const InspectionResult& r) {
  ResultClouds out;
  const Cloud& c = r.cloud;
  // 0 rest, 1 cable, 2 interference (interference wins: it is what a person looks for).
  std::vector<std::uint8_t> kind(c.size(), 0);
  std::vector<Rgb> color(c.size(), Rgb{160, 160, 160});
  for (std::size_t k = 0; k < r.cables.size(); ++k) {
    if (!r.cables[k].found) continue;
    for (std::uint32_t i : r.cables[k].trace.points)
      if (i < c.size()) {
        kind[i] = 1;
        color[i] = cable_color(k);
      }
  }
  for (const CableInspection& ci : r.cables)
    for (const Interference& f : ci.interferences) {
      const Rgb col = f.with ? Rgb{255, 140, 0} : Rgb{230, 20, 20};  // orange: a CAD element, red: foreign
      for (std::uint32_t i : f.points)
        if (i < c.size() && kind[i] != 1) {
          kind[i] = 2;
          color[i] = col;
        }
    }
  for (std::size_t i = 0; i < c.size(); ++i) {
    Cloud& dst = kind[i] == 1 ? out.cables : (kind[i] == 2 ? out.interferences : out.rest);
    dst.points.push_back(c.points[i]);
    dst.colors.push_back(color[i]);
  }
  return out;
}

}  // namespace ewis
