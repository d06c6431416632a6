// Beyond the paper (issue 7, 4b): greedy set cover of several elements' surfaces by candidate viewpoints.
#include "ewis/plan/coverage.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <random>

#include "ewis/core/parallel.hpp"

namespace ewis {
namespace {

double uniform01(std::mt19937_64& rng) { return double(rng() >> 11) * 0x1.0p-53; }  // portable, unlike <random>'s

std::uint64_t mix_seed(std::uint64_t seed, std::uint64_t k) {  // splitmix64 of (seed, k)
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ull + k + 0x632BE59BD9B4E019ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

SurfaceSamples sample_elements(const Scene& scene, const std::vector<std::uint32_t>& elements,
                               std::size_t per_element, std::uint64_t seed) {
  SurfaceSamples out;
  out.element_begin.push_back(0);
  for (std::size_t k = 0; k < elements.size(); ++k) {
    const std::uint32_t e = elements[k];
    if (e < scene.elements.size()) {
      const Element& el = scene.elements[e];
      const std::uint32_t first = el.first_triangle;
      const std::uint32_t end = std::min<std::uint64_t>(std::uint64_t(first) + el.triangle_count, scene.triangles.size());
      std::vector<double> cumulative;
      cumulative.reserve(end > first ? end - first : 0);
      double total = 0.0;
      for (std::uint32_t t = first; t < end; ++t) {
        const Eigen::Vector3i& tri = scene.triangles[t];
        const Eigen::Vector3d a = scene.vertices[tri[0]].cast<double>();
        total += 0.5 * (scene.vertices[tri[1]].cast<double>() - a).cross(scene.vertices[tri[2]].cast<double>() - a).norm();
        cumulative.push_back(total);
      }
      if (total > 0) {
        std::mt19937_64 rng(mix_seed(seed, e));
        for (std::size_t i = 0; i < per_element; ++i) {
          const double pick = uniform01(rng) * total;
          const std::size_t j = std::min<std::size_t>(
              std::upper_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin(), cumulative.size() - 1);
          const Eigen::Vector3i& tri = scene.triangles[first + j];
          const Eigen::Vector3d a = scene.vertices[tri[0]].cast<double>();
          const Eigen::Vector3d b = scene.vertices[tri[1]].cast<double>();
          const Eigen::Vector3d c = scene.vertices[tri[2]].cast<double>();
          const Eigen::Vector3d n = (b - a).cross(c - a);
          if (!(n.norm() > 0)) continue;
          // Uniform point in a triangle: sqrt-warped barycentrics.
          const double r1 = std::sqrt(uniform01(rng)), r2 = uniform01(rng);
          out.points.push_back(a * (1 - r1) + b * (r1 * (1 - r2)) + c * (r1 * r2));
          out.normals.push_back(n.normalized());
        }
      }
    }
    out.element_begin.push_back(out.points.size());
  }
  return out;
}

VisibilitySets visible_samples(const Raycaster& scene_caster, const Camera& camera, const std::vector<Pose>& views,
                               const std::vector<bool>& usable, const SurfaceSamples& samples,
                               const CoverageParams& params, const ProgressFn& progress) {
  VisibilitySets sets;
  const std::size_t elements = samples.element_begin.empty() ? 0 : samples.element_begin.size() - 1;
  sets.element_word_begin.push_back(0);
  for (std::size_t k = 0; k < elements; ++k) {
    const std::size_t n = samples.element_begin[k + 1] - samples.element_begin[k];
    sets.element_samples.push_back(n);
    sets.element_word_begin.push_back(sets.element_word_begin.back() + (n + 63) / 64);
  }
  sets.words = sets.element_word_begin.back();
  sets.seen.assign(views.size(), std::vector<std::uint64_t>(sets.words, 0));
  const double max_incidence = params.measurable ? params.sensor.max_incidence_deg : params.max_incidence_deg;
  const double cos_max = std::cos(max_incidence * M_PI / 180.0);
  const Camera::Projection projection = camera.projection();
  std::atomic<std::size_t> done{0};
  parallel_for_each_index(
      views.size(),
      [&](std::size_t v) {
        if (v < usable.size() && !usable[v]) return;
        const Pose& pose = views[v];
        const Pose cad_to_camera = pose.inverse();
        const Eigen::Vector3d eye = pose.translation();
        const Eigen::Vector3d projector = eye + params.sensor.baseline_mm * pose.linear().col(0);
        auto& bits = sets.seen[v];
        for (std::size_t k = 0; k < elements; ++k) {
          const std::size_t begin = samples.element_begin[k], word0 = sets.element_word_begin[k];
          for (std::size_t s = begin; s < samples.element_begin[k + 1]; ++s) {
            const Eigen::Vector3d& p = samples.points[s];
            double u = 0, vv = 0;
            if (!projection.project(cad_to_camera * p, u, vv) || !camera.inside(u, vv)) continue;
            Eigen::Vector3d dir = p - eye;
            const double dist = dir.norm();
            if (!(dist > 0)) continue;
            dir /= dist;
            // Two-sided: CAD winding is not always consistent; the normal that faces the camera.
            Eigen::Vector3d n = samples.normals[s];
            if (n.dot(dir) > 0) n = -n;
            if (-n.dot(dir) < cos_max) continue;
            const double eps = 0.05 + 1e-4 * dist;
            Ray ray;
            ray.origin = eye.cast<float>();
            ray.direction = dir.cast<float>();
            ray.tmax_mm = static_cast<float>(dist - eps);
            if (scene_caster.occluded(ray)) continue;
            if (params.measurable) {
              Eigen::Vector3d to_projector = projector - p;
              const double pd = to_projector.norm();
              if (!(pd > 0)) continue;
              to_projector /= pd;
              if (to_projector.dot(n) < cos_max) continue;
              Ray shadow;
              shadow.origin = (p + n * eps).cast<float>();
              shadow.direction = to_projector.cast<float>();
              shadow.tmax_mm = static_cast<float>(pd - 2 * eps);
              if (scene_caster.occluded(shadow)) continue;
            }
            const std::size_t local = s - begin;
            bits[word0 + local / 64] |= std::uint64_t(1) << (local % 64);
          }
        }
        const std::size_t d = ++done;
        if (progress) progress("plan: coverage", double(d) / double(views.size()));
      },
      1);
  return sets;
}

CoverResult greedy_cover(const VisibilitySets& sets, double target_fraction, std::size_t max_viewpoints,
                         double min_gain_fraction) {
  CoverResult result;
  const std::size_t elements = sets.element_samples.size();
  std::vector<std::size_t> need(elements), have(elements, 0);
  for (std::size_t k = 0; k < elements; ++k)
    need[k] = static_cast<std::size_t>(std::ceil(std::clamp(target_fraction, 0.0, 1.0) * sets.element_samples[k] - 1e-9));
  auto count_in = [&](const std::vector<std::uint64_t>& bits, const std::vector<std::uint64_t>* covered, std::size_t k) {
    std::size_t c = 0;
    for (std::size_t w = sets.element_word_begin[k]; w < sets.element_word_begin[k + 1]; ++w)
      c += std::popcount(covered ? bits[w] & ~(*covered)[w] : bits[w]);
    return c;
  };
  // What any candidate sees at all: a target beyond it cannot be met, so greedy aims at the reachable part
  // (else it would keep adding views that each add a sample or two).
  std::vector<std::uint64_t> any(sets.words, 0);
  for (const auto& bits : sets.seen)
    for (std::size_t w = 0; w < sets.words; ++w) any[w] |= bits[w];
  result.reachable.assign(elements, 0.0);
  for (std::size_t k = 0; k < elements; ++k) {
    const std::size_t reach = count_in(any, nullptr, k);
    if (sets.element_samples[k] > 0) result.reachable[k] = double(reach) / double(sets.element_samples[k]);
    need[k] = std::min(need[k], reach);
  }
  // Per element, the best any single view does: a lower bound on the optimum and the greedy factor.
  result.best_single.assign(elements, 0.0);
  std::size_t max_single_value = 0;
  std::vector<std::size_t> best_count(elements, 0);
  for (const auto& bits : sets.seen) {
    std::size_t value = 0;
    for (std::size_t k = 0; k < elements; ++k) {
      const std::size_t c = count_in(bits, nullptr, k);
      best_count[k] = std::max(best_count[k], c);
      value += std::min(c, need[k]);
    }
    max_single_value = std::max(max_single_value, value);
  }
  for (std::size_t k = 0; k < elements; ++k) {
    if (sets.element_samples[k] > 0) result.best_single[k] = double(best_count[k]) / double(sets.element_samples[k]);
    if (need[k] > 0 && best_count[k] > 0)
      result.lower_bound = std::max(result.lower_bound, (need[k] + best_count[k] - 1) / best_count[k]);
  }
  result.greedy_factor = 1.0 + std::log(double(std::max<std::size_t>(max_single_value, 1)));

  std::vector<std::uint64_t> covered(sets.words, 0);
  std::vector<bool> taken(sets.seen.size(), false);
  auto satisfied = [&] {
    for (std::size_t k = 0; k < elements; ++k)
      if (have[k] < need[k]) return false;
    return true;
  };
  for (std::size_t step = 0; step < max_viewpoints && !satisfied(); ++step) {
    std::size_t best = sets.seen.size(), best_gain = 0;
    for (std::size_t v = 0; v < sets.seen.size(); ++v) {  // ties: the lowest index (candidate order)
      if (taken[v]) continue;
      std::size_t gain = 0;
      for (std::size_t k = 0; k < elements; ++k)
        if (have[k] < need[k]) gain += std::min(count_in(sets.seen[v], &covered, k), need[k] - have[k]);
      if (gain > best_gain) best_gain = gain, best = v;
    }
    if (best_gain == 0) break;  // nothing left can be seen: the target is out of reach
    std::size_t smallest = 0;    // samples of the smallest unfinished element
    for (std::size_t k = 0; k < elements; ++k)
      if (have[k] < need[k] && (smallest == 0 || sets.element_samples[k] < smallest)) smallest = sets.element_samples[k];
    if (double(best_gain) < min_gain_fraction * double(smallest)) break;  // only the long tail is left
    taken[best] = true;
    std::vector<double> gained(elements, 0.0);
    for (std::size_t k = 0; k < elements; ++k) {
      const std::size_t c = count_in(sets.seen[best], &covered, k);
      have[k] += c;
      if (sets.element_samples[k] > 0) gained[k] = double(c) / double(sets.element_samples[k]);
    }
    for (std::size_t w = 0; w < sets.words; ++w) covered[w] |= sets.seen[best][w];
    result.chosen.push_back(best);
    result.gained.push_back(std::move(gained));
  }
  result.coverage.assign(elements, 0.0);
  result.complete = true;
  for (std::size_t k = 0; k < elements; ++k) {
    result.coverage[k] = sets.element_samples[k] > 0 ? double(have[k]) / double(sets.element_samples[k]) : 0.0;
    if (sets.element_samples[k] > 0 && result.coverage[k] + 1e-12 < target_fraction) result.complete = false;
  }
  return result;
}

}  // namespace ewis
