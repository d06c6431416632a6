#include <array>

#include "ewis/inspect/pipeline.hpp"
#include "ewis/io/cloud_io.hpp"

namespace ewis {

Rgb cable_color(std::size_t index) {
  static const std::array<Rgb, 8> palette = {{{31, 119, 180}, {44, 160, 44}, {148, 103, 189}, {23, 190, 207},
                                              {188, 189, 34}, {227, 119, 194}, {140, 86, 75}, {127, 127, 255}}};
  return palette[index % palette.size()];
}

namespace {

// Per point: 0 rest, 1 + k % 8 a point of cable k (its palette colour), kClash / kForeign a point of an
// interference cluster (with a CAD element / foreign). A cable point stays a cable point; later clusters win
// over earlier ones (it is what a person looks for).
constexpr std::uint16_t kClash = 65534, kForeign = 65535;
enum class ResultPart { Cables, Interferences, Rest };

std::vector<std::uint16_t> point_tags(const InspectionResult& r) {
  const std::size_t n = r.cloud.size();
  std::vector<std::uint16_t> tag(n, 0);
  for (std::size_t k = 0; k < r.cables.size(); ++k) {
    if (!r.cables[k].found) continue;
    const auto t = static_cast<std::uint16_t>(1 + k % 8);  // the palette has 8 colours
    for (std::uint32_t i : r.cables[k].trace.points)
      if (i < n) tag[i] = t;
  }
  for (const CableInspection& ci : r.cables)
    for (const Interference& f : ci.interferences)
      for (std::uint32_t i : f.points)
        if (i < n && (tag[i] == 0 || tag[i] >= kClash)) tag[i] = f.with ? kClash : kForeign;
  return tag;
}

Cloud part_of(const InspectionResult& r, const std::vector<std::uint16_t>& tag, ResultPart part) {
  auto in_part = [&](std::uint16_t t) {
    switch (part) {
      case ResultPart::Cables: return t > 0 && t < kClash;
      case ResultPart::Interferences: return t >= kClash;
      case ResultPart::Rest: return t == 0;
    }
    return false;
  };
  std::size_t count = 0;
  for (std::uint16_t t : tag) count += in_part(t);
  Cloud out;
  out.points.reserve(count);
  out.colors.reserve(count);
  for (std::size_t i = 0; i < tag.size(); ++i) {
    const std::uint16_t t = tag[i];
    if (!in_part(t)) continue;
    out.points.push_back(r.cloud.points[i]);
    out.colors.push_back(t == 0 ? Rgb{160, 160, 160}
                                : t == kClash ? Rgb{255, 140, 0}      // orange: a CAD element
                                : t == kForeign ? Rgb{230, 20, 20}    // red: foreign
                                : cable_color(t - 1u));
  }
  return out;
}

}  // namespace

ResultClouds result_clouds(const InspectionResult& r) {
  const std::vector<std::uint16_t> tag = point_tags(r);
  ResultClouds out;
  out.cables = part_of(r, tag, ResultPart::Cables);
  out.interferences = part_of(r, tag, ResultPart::Interferences);
  out.rest = part_of(r, tag, ResultPart::Rest);
  return out;
}

void write_result_clouds(const InspectionResult& r, const std::string& dir) {
  const std::vector<std::uint16_t> tag = point_tags(r);  // once for the three files
  write_ply(part_of(r, tag, ResultPart::Cables), dir + "/cables.ply");
  write_ply(part_of(r, tag, ResultPart::Interferences), dir + "/interferences.ply");
  write_ply(part_of(r, tag, ResultPart::Rest), dir + "/rest.ply");
}

}  // namespace ewis
