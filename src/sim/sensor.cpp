// Virtual structured-light sensor (see sensor.hpp): camera rays, projector shadow rays, noise along the ray.
#include "ewis/sim/sensor.hpp"

#include <algorithm>
#include <cmath>

#include "ewis/core/parallel.hpp"
#include "rng.hpp"

namespace ewis::sim {

void add_outliers(const Camera& camera, const std::vector<float>& depth, const SensorParams& params,
                  ScanResult& out);  // outliers.cpp
void add_mismatch_patches(const Camera& camera, const std::vector<std::uint32_t>& valid, std::vector<float>& depth,
                          const SensorParams& params, ScanResult& out);  // outliers.cpp

ScanResult scan(const Raycaster& caster, const Camera& camera, const Pose& camera_to_world,
                const SensorParams& params) {
  const int w = camera.width_px, h = camera.height_px;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  const Eigen::Matrix3d rot = camera_to_world.linear();
  const Eigen::Vector3d origin = camera_to_world.translation();
  const Eigen::Vector3f origin_f = origin.cast<float>();

  // Camera rays through every pixel centre, unit directions in the world frame.
  std::vector<Ray> rays(n);
  parallel_for_each_index(n, [&](std::size_t i) {
    const Eigen::Vector3d d = rot * camera.pixel_ray(static_cast<int>(i % w), static_cast<int>(i / w)).normalized();
    rays[i] = Ray{origin_f, d.cast<float>(), static_cast<float>(params.max_range_mm)};
  });
  std::vector<Hit> hits;
  caster.cast(rays, hits);

  // Projector rays toward each candidate surface point (stereo shadowing), after the incidence test.
  const Eigen::Vector3d projector = camera_to_world * Eigen::Vector3d(params.baseline_mm, 0.0, 0.0);
  const double cos_limit = std::cos(params.max_incidence_deg * M_PI / 180.0);
  std::vector<std::uint8_t> state(n, 0);  // 0 no hit, 1 candidate, 2 grazing
  parallel_for_each_index(n, [&](std::size_t i) {
    const Hit& hit = hits[i];
    if (!hit.hit() || hit.distance_mm < params.min_range_mm || hit.distance_mm > params.max_range_mm) return;
    const Eigen::Vector3d dir = rays[i].direction.cast<double>();
    const Eigen::Vector3d nrm = hit.normal.cast<double>();
    const Eigen::Vector3d x = origin + dir * double(hit.distance_mm);
    const Eigen::Vector3d to_proj = projector - x;
    const double cos_cam = std::abs(nrm.dot(dir));
    const double cos_proj = nrm.dot(to_proj) / to_proj.norm() * (nrm.dot(-dir) >= 0 ? 1.0 : -1.0);
    state[i] = (cos_cam < cos_limit || cos_proj < cos_limit) ? 2 : 1;
  });
  const std::vector<std::uint32_t> cand = parallel_select(n, [&](std::size_t i) { return state[i] == 1; });
  std::vector<Ray> shadow(cand.size());
  parallel_for_each_index(cand.size(), [&](std::size_t k) {
    const std::size_t i = cand[k];
    const Eigen::Vector3d x = origin + rays[i].direction.cast<double>() * double(hits[i].distance_mm);
    const Eigen::Vector3d d = x - projector;
    const double len = d.norm();
    // Stop short of the point itself (float hit positions are good to ~1e-4 mm at 600 mm).
    shadow[k] = Ray{projector.cast<float>(), (d / len).cast<float>(), static_cast<float>(len - std::max(0.05, 2e-4 * len))};
  });
  std::vector<Hit> shadow_hits;
  caster.cast(shadow, shadow_hits);

  ScanResult out;
  std::vector<float> depth(n, std::numeric_limits<float>::infinity());  // measured range per pixel
  std::vector<std::uint8_t> lit(n, 0);
  for (std::size_t k = 0; k < cand.size(); ++k)
    if (!shadow_hits[k].hit()) lit[cand[k]] = 1;
  for (std::size_t i = 0; i < n; ++i) {
    if (hits[i].hit()) ++out.camera_hits;
    if (state[i] == 2) ++out.grazing;
  }
  out.shadowed = cand.size();
  const std::vector<std::uint32_t> valid = parallel_select(n, [&](std::size_t i) { return lit[i] != 0; });
  out.shadowed -= valid.size();

  // Noise along the ray: sigma = sigma600 (d / 600)^2, one seeded generator per pixel.
  const double sigma600 = params.noise_free ? 0.0 : params.sigma600_mm;
  out.cloud.points.resize(valid.size());
  out.kind.assign(valid.size(), PointKind::Surface);
  out.element.resize(valid.size());
  out.pixel.assign(valid.begin(), valid.end());
  parallel_for_each_index(valid.size(), [&](std::size_t k) {
    const std::size_t i = valid[k];
    const double d = hits[i].distance_mm;
    double dm = d;
    if (sigma600 > 0) {
      Rng rng(mix(params.seed, i, 1));
      dm += sigma600 * (d / 600.0) * (d / 600.0) * rng.normal();
    }
    const Eigen::Vector3d dir_cam = camera.pixel_ray(static_cast<int>(i % w), static_cast<int>(i / w)).normalized();
    out.cloud.points[k] = (dir_cam * dm).cast<float>();
    out.element[k] = hits[i].element;
    depth[i] = static_cast<float>(dm);
  });
  out.surface_points = valid.size();
  if (!params.noise_free && params.mismatch_patches > 0) add_mismatch_patches(camera, valid, depth, params, out);
  if (!params.noise_free && params.outlier_fraction > 0) add_outliers(camera, depth, params, out);
  out.outliers = out.cloud.size() - out.surface_points;
  return out;
}

}  // namespace ewis::sim
