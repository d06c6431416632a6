// Clumps standing off a cable's surface by a step (see surface_clumps.hpp).
#include "ewis/inspect/surface_clumps.hpp"

#include <algorithm>
#include <cmath>

#include "ewis/core/cylinder.hpp"
#include "ewis/core/parallel.hpp"
#include "ewis/core/robust.hpp"
#include "ewis/filter/euclidean_clusters.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis {
namespace {

// Distance across the ray from the sensor through `on_ray` between it and `q`.
double across_ray(const Eigen::Vector3d& on_ray, const Eigen::Vector3d& sensor, const Eigen::Vector3d& q) {
  const Eigen::Vector3d u = (on_ray - sensor).normalized();
  const Eigen::Vector3d d = q - on_ray;
  return (d - d.dot(u) * u).norm();
}

}  // namespace

SurfaceClumps surface_step_clumps(const std::vector<Eigen::Vector3d>& points,
                                  const std::vector<Eigen::Vector3d>& centerline, double tube_radius_mm,
                                  const Eigen::Vector3d& sensor, double resolution_mm,
                                  const SurfaceClumpParams& params) {
  SurfaceClumps out;
  if (!params.enabled || points.size() < params.min_points || centerline.size() < 2 || !(tube_radius_mm > 0) ||
      !(resolution_mm > 0))
    return out;

  // Each point's offset from the tube: its distance to the centreline polyline less the radius.
  std::vector<Eigen::Vector3f> cl(centerline.size());
  for (std::size_t i = 0; i < centerline.size(); ++i) cl[i] = centerline[i].cast<float>();
  const KdTree cl_tree(cl);
  std::vector<double> offset(points.size(), 0.0);
  parallel_for_each_index(points.size(), [&](std::size_t i) {
    const std::uint32_t j = cl_tree.nearest(points[i].cast<float>()).index;
    double d = (centerline[j] - points[i]).norm();
    if (j > 0) d = std::min(d, distance_to_segment(Cylinder{centerline[j - 1], centerline[j], 0.0}, points[i]));
    if (j + 1 < centerline.size())
      d = std::min(d, distance_to_segment(Cylinder{centerline[j], centerline[j + 1], 0.0}, points[i]));
    offset[i] = d - tube_radius_mm;
  }, 4096);
  double median = 0.0, sigma = 0.0;
  std::vector<double> tmp;
  median_and_robust_sigma(offset, params.min_noise_mm, tmp, median, sigma);
  out.sigma_mm = sigma;
  for (double& r : offset) r -= median;
  const double threshold = std::max(params.min_offset_sigmas * sigma, params.min_offset_mm);

  std::vector<std::uint32_t> off;
  std::vector<std::uint8_t> is_off(points.size(), 0);
  for (std::size_t i = 0; i < points.size(); ++i)
    if (std::abs(offset[i]) > threshold) off.push_back(std::uint32_t(i)), is_off[i] = 1;
  if (off.size() < params.min_points) return out;

  std::vector<Eigen::Vector3f> pf(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) pf[i] = points[i].cast<float>();
  const KdTree tree(pf);
  const double link = params.link_resolutions * resolution_mm;
  const double ring = params.ring_resolutions * resolution_mm;
  const ClusterResult clusters = euclidean_clusters(tree, off, link, params.min_points);
  std::vector<Neighbor> nbs;
  std::vector<double> steps, clump_offsets;
  std::vector<std::int32_t> slot(points.size(), -1);  // a ring point's place in ring_points
  std::vector<std::uint32_t> ring_points;
  std::vector<std::pair<double, double>> ring_best;   // its least across-ray distance to the clump, and the step there
  std::vector<std::uint8_t> taken(points.size(), 0);  // in a clump found (grown)
  for (const std::vector<std::uint32_t>& c : clusters.clusters) {
    // All off to one side (a patch moves along its rays by one offset).
    clump_offsets.clear();
    for (std::uint32_t i : c) clump_offsets.push_back(offset[i]);
    const double side = offset[c.front()] > 0 ? 1.0 : -1.0;
    if (std::any_of(clump_offsets.begin(), clump_offsets.end(), [&](double r) { return r * side <= 0; })) continue;
    const double level = std::abs(median_in_place(clump_offsets));
    // Its neighbours in the image: points off nothing, within `ring` of a clump point across its ray (they lie up to
    // the clump's offset away along it); each one's step from the nearest such clump point.
    double widest = 0.0;
    for (std::uint32_t i : c) widest = std::max(widest, std::abs(offset[i]));
    ring_points.clear();
    for (std::uint32_t i : c) {
      tree.radius_unsorted(pf[i], float(ring + widest + threshold), nbs);
      for (const Neighbor& nb : nbs) {
        const std::uint32_t q = nb.index;
        if (is_off[q]) continue;
        const double across = across_ray(points[i], sensor, points[q]);
        if (across > ring) continue;
        const double step = side * (offset[i] - offset[q]);
        if (slot[q] < 0) {
          slot[q] = std::int32_t(ring_points.size());
          ring_points.push_back(q);
          ring_best.push_back({across, step});
        } else if (across < ring_best[std::size_t(slot[q])].first) {
          ring_best[std::size_t(slot[q])] = {across, step};
        }
      }
    }
    steps.clear();
    for (const auto& b : ring_best) steps.push_back(b.second);
    for (std::uint32_t q : ring_points) slot[q] = -1;
    ring_best.clear();
    if (steps.size() < params.min_ring_points) continue;
    const double edge = median_in_place(steps);
    if (edge < threshold || edge < params.min_step_fraction * level) continue;
    // Grown over the points next to it off to the same side by grow_fraction of its offset: the patch's rim, where its
    // rays meet the tube aslant and the move shows less across the surface.
    const double grow_level = std::max(params.grow_fraction * level, params.grow_min_sigmas * sigma);
    std::vector<std::uint32_t> grown;  // (a clump found before may have grown over some of this one)
    for (std::uint32_t i : c)
      if (!taken[i]) taken[i] = 1, grown.push_back(i);
    for (std::size_t g = 0; g < grown.size(); ++g) {
      tree.radius_unsorted(pf[grown[g]], float(link), nbs);
      for (const Neighbor& nb : nbs)
        if (!taken[nb.index] && side * offset[nb.index] > grow_level) {
          taken[nb.index] = 1;
          grown.push_back(nb.index);
        }
    }
    out.points.insert(out.points.end(), grown.begin(), grown.end());
    ++out.clumps;
  }
  std::sort(out.points.begin(), out.points.end());
  return out;
}

}  // namespace ewis
