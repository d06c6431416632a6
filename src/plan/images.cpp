// Pictures for a person checking the plan (issue 7, output): which view was chosen, and where good views are.
#include "ewis/plan/images.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace ewis {
namespace {

using Colour = std::array<double, 3>;

// A compact viridis-like ramp: dark blue, teal, green, yellow.
Colour ramp(double t) {
  static const std::array<Colour, 5> stops = {Colour{68, 1, 84}, Colour{59, 82, 139}, Colour{33, 145, 140},
                                              Colour{94, 201, 98}, Colour{253, 231, 37}};
  t = std::clamp(t, 0.0, 1.0) * (stops.size() - 1);
  const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(t), stops.size() - 2);
  const double f = t - double(i);
  Colour c;
  for (int k = 0; k < 3; ++k) c[k] = stops[i][k] * (1 - f) + stops[i + 1][k] * f;
  return c;
}

void put(Image& img, int col, int row, const Colour& c) {
  if (col < 0 || row < 0 || col >= img.width_px || row >= img.height_px) return;
  std::uint8_t* p = img.at(col, row);
  for (int k = 0; k < 3; ++k) p[k] = static_cast<std::uint8_t>(std::clamp(std::lround(c[k]), 0L, 255L));
}

}  // namespace

Image render_highlight(const Raycaster& caster, const Camera& camera, const Pose& camera_to_cad,
                       const std::vector<std::uint32_t>& primary, const std::vector<std::uint32_t>& secondary) {
  const Render r = render(caster, camera, camera_to_cad);
  Image img(r.width_px, r.height_px, 255);
  const Eigen::Matrix3d R = camera_to_cad.linear();
  for (int row = 0; row < r.height_px; ++row) {
    for (int col = 0; col < r.width_px; ++col) {
      const std::size_t i = std::size_t(row) * r.width_px + col;
      const std::uint32_t e = r.element[i];
      if (e == kNoElement) continue;
      const Eigen::Vector3d dir = (R * camera.pixel_ray(col, row)).normalized();
      const double shade = 0.3 + 0.7 * std::abs(dir.dot(r.normal[i].cast<double>()));
      Colour base{200, 200, 200};
      if (std::find(primary.begin(), primary.end(), e) != primary.end()) base = {235, 30, 30};
      else if (std::find(secondary.begin(), secondary.end(), e) != secondary.end()) base = {245, 150, 40};
      put(img, col, row, {base[0] * shade, base[1] * shade, base[2] * shade});
    }
  }
  return img;
}

Image score_heatmap(const CandidateGrid& grid, const std::vector<CandidateScore>& scores,
                    const std::vector<std::size_t>& marked, int cell_px) {
  cell_px = std::clamp(cell_px, 2, 64);
  const int nt = static_cast<int>(grid.theta_deg.size()), np = static_cast<int>(grid.phi_deg.size());
  const int bar_px = 12, gap_px = 4;
  Image img(std::max(nt * cell_px, 64), np * cell_px + gap_px + bar_px, 255);
  std::uint64_t top = 0;
  for (const auto& s : scores) top = std::max(top, s.score_px);
  for (std::size_t i = 0; i < grid.candidates.size() && i < scores.size(); ++i) {
    const Candidate& c = grid.candidates[i];
    const int x0 = c.theta_index * cell_px, y0 = c.phi_index * cell_px;
    for (int y = 0; y < cell_px; ++y)
      for (int x = 0; x < cell_px; ++x) {
        Colour col = ramp(top > 0 ? double(scores[i].score_px) / double(top) : 0.0);
        if (scores[i].rejected) col = (x == y || x == cell_px - 1 - y) ? Colour{90, 90, 90} : Colour{170, 170, 170};
        put(img, x0 + x, y0 + y, col);
      }
  }
  for (std::size_t m : marked) {
    if (m >= grid.candidates.size()) continue;
    const int x0 = grid.candidates[m].theta_index * cell_px, y0 = grid.candidates[m].phi_index * cell_px;
    for (int k = 0; k < cell_px; ++k) {
      put(img, x0 + k, y0, {255, 255, 255}), put(img, x0 + k, y0 + cell_px - 1, {255, 255, 255});
      put(img, x0, y0 + k, {255, 255, 255}), put(img, x0 + cell_px - 1, y0 + k, {255, 255, 255});
    }
  }
  for (int x = 0; x < img.width_px; ++x)
    for (int y = 0; y < bar_px; ++y) put(img, x, np * cell_px + gap_px + y, ramp(double(x) / (img.width_px - 1)));
  return img;
}

}  // namespace ewis
