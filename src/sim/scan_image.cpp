// A picture of what the sensor saw: every point (outliers included) splatted into its pixel, nearest wins,
// coloured by range (near: warm, far: cool) between the 1st and 99th percentile of the ranges.
#include <algorithm>
#include <cmath>

#include "ewis/sim/campaign.hpp"

namespace ewis::sim {

namespace {
// Compact approximation of the "turbo" colour map, t in [0, 1].
void turbo(double t, std::uint8_t* rgb) {
  t = std::clamp(t, 0.0, 1.0);
  const double r = 0.1357 + t * (4.5974 - t * (42.3277 - t * (130.5887 - t * (150.5666 - t * 58.1375))));
  const double g = 0.0914 + t * (2.1856 + t * (4.8052 - t * (14.0195 - t * (4.2109 + t * 2.7747))));
  const double b = 0.1067 + t * (12.5925 - t * (60.1097 - t * (109.0745 - t * (88.5066 - t * 26.8183))));
  rgb[0] = static_cast<std::uint8_t>(std::clamp(r, 0.0, 1.0) * 255.0 + 0.5);
  rgb[1] = static_cast<std::uint8_t>(std::clamp(g, 0.0, 1.0) * 255.0 + 0.5);
  rgb[2] = static_cast<std::uint8_t>(std::clamp(b, 0.0, 1.0) * 255.0 + 0.5);
}
}  // namespace

Image scan_image(const Cloud& cloud, const Camera& camera) {
  Image img(camera.width_px, camera.height_px, 24);
  if (cloud.empty()) return img;
  std::vector<float> zbuf(std::size_t(camera.width_px) * camera.height_px, std::numeric_limits<float>::infinity());
  std::vector<float> ranges;
  ranges.reserve(cloud.size());
  const Camera::Projection projection = camera.projection();
  for (const auto& p : cloud.points) {
    double u, v;
    if (!projection.project(p.cast<double>(), u, v) || !camera.inside(u, v)) continue;
    const std::size_t i = std::size_t(int(v)) * camera.width_px + int(u);
    const float r = p.norm();
    zbuf[i] = std::min(zbuf[i], r);
    ranges.push_back(r);
  }
  if (ranges.empty()) return img;
  const std::size_t lo_i = ranges.size() / 100, hi_i = ranges.size() - 1 - ranges.size() / 100;
  std::nth_element(ranges.begin(), ranges.begin() + lo_i, ranges.end());
  const double lo = ranges[lo_i];
  std::nth_element(ranges.begin(), ranges.begin() + hi_i, ranges.end());
  const double hi = std::max(lo + 1.0, double(ranges[hi_i]));
  for (int r = 0; r < camera.height_px; ++r)
    for (int c = 0; c < camera.width_px; ++c) {
      const float z = zbuf[std::size_t(r) * camera.width_px + c];
      if (std::isfinite(z)) turbo(1.0 - (z - lo) / (hi - lo), img.at(c, r));
    }
  return img;
}

}  // namespace ewis::sim
