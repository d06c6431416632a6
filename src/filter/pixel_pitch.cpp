// The sensor's angular pixel pitch from the rays of a scan (filter/pixel_pitch.hpp).
#include "ewis/filter/pixel_pitch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "ewis/core/parallel.hpp"

namespace ewis {

double angular_pixel_pitch_rad(const KdTree& tree, const Eigen::Vector3d& sensor, double resolution_mm,
                               const PixelPitchParams& params) {
  const std::size_t n = tree.size();
  if (n < 2 || !(resolution_mm > 0) || !(params.disc_resolutions > 0) || params.max_samples == 0) return 0.0;
  const std::size_t stride = (n + params.max_samples - 1) / params.max_samples;
  const std::size_t samples = (n + stride - 1) / stride;
  const std::vector<Eigen::Vector3f>& points = tree.points();
  const double ball_mm = std::max(params.ball_resolutions, params.disc_resolutions) * resolution_mm;
  const double cell_mm = 0.25 * resolution_mm;
  // Each sample's pitch lands in its own slot: the query order cannot change the result.
  std::vector<double> pitch(samples, std::numeric_limits<double>::quiet_NaN());
  parallel_blocks(samples, 64, [&](std::size_t b, std::size_t e) {
    std::vector<Neighbor> around;
    std::vector<std::pair<long, long>> cells;
    for (std::size_t s = b; s < e; ++s) {
      const Eigen::Vector3d x = points[s * stride].cast<double>();
      if (!x.allFinite()) continue;
      const double range = (x - sensor).norm();
      if (!(range > ball_mm)) continue;
      const Eigen::Vector3d ray = (x - sensor) / range;
      // The disc's angle, compared as the chord between unit rays (2 sin(rho / 2)).
      const double rho = params.disc_resolutions * resolution_mm / range;
      const double chord_sq = std::pow(2.0 * std::sin(0.5 * rho), 2);
      tree.radius_unsorted(points[s * stride], float(ball_mm), around);
      // Rays, not points: the disc's points where their rays cross the plane across this ray at its range, on a grid
      // of a quarter resolution, each cell once (a stack of points on one ray, as mixed pixels and a sensor's repeated
      // ranges give, is one pixel; as in InterferenceParams' footprints).
      const Eigen::Vector3d a = ray.unitOrthogonal(), c = ray.cross(a);
      cells.clear();
      for (const Neighbor& nb : around) {
        const Eigen::Vector3d y = (points[nb.index].cast<double>() - sensor).normalized();
        if ((y - ray).squaredNorm() > chord_sq) continue;
        const Eigen::Vector3d q = y * (range / std::max(y.dot(ray), 1e-6)) - ray * range;
        cells.emplace_back(std::lround(std::floor(q.dot(a) / cell_mm)), std::lround(std::floor(q.dot(c) / cell_mm)));
      }
      std::sort(cells.begin(), cells.end());
      const std::size_t in_disc = std::size_t(std::unique(cells.begin(), cells.end()) - cells.begin());
      if (in_disc >= params.min_points) pitch[s] = rho * std::sqrt(M_PI / double(in_disc));
    }
  });
  pitch.erase(std::remove_if(pitch.begin(), pitch.end(), [](double p) { return !std::isfinite(p); }), pitch.end());
  if (pitch.empty()) return 0.0;
  const auto mid = pitch.begin() + static_cast<std::ptrdiff_t>(pitch.size() / 2);
  std::nth_element(pitch.begin(), mid, pitch.end());
  return *mid;
}

}  // namespace ewis
