#pragma once
// A small virtual range sensor for the tubes tests: analytic surfaces sampled densely, seen from a sensor
// at the origin through a z-buffer (~0.5 mm pixels at 600 mm), noise along the viewing rays, and outliers
// (uniform ones and "flying pixel" clusters of 2-4 points along the rays), as DESIGN.md's hard cases ask.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <random>
#include <unordered_map>
#include <vector>

#include "ewis/core/cloud.hpp"

namespace synth {

struct Sample {
  Eigen::Vector3d p, n;
  int id;
};

struct Scene {
  std::vector<Sample> samples;
  double spacing = 0.2;  // surface sampling (finer than the pixels, so the z-buffer has no holes)

  // A tube of radius r around a centreline given as a dense polyline (steps << r).
  void add_tube(const std::vector<Eigen::Vector3d>& line, double r, int id) {
    double carry = 0;
    for (std::size_t i = 0; i + 1 < line.size(); ++i) {
      const Eigen::Vector3d a = line[i], b = line[i + 1];
      const double len = (b - a).norm();
      const Eigen::Vector3d t = (b - a) / len;
      const Eigen::Vector3d ref = std::abs(t.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
      const Eigen::Vector3d e1 = t.cross(ref).normalized(), e2 = t.cross(e1);
      const int m = static_cast<int>(std::ceil(2 * M_PI * r / spacing));
      double s = carry;
      for (; s < len; s += spacing) {
        const Eigen::Vector3d c = a + t * s;
        for (int k = 0; k < m; ++k) {
          const double ang = 2 * M_PI * k / m;
          const Eigen::Vector3d nrm = std::cos(ang) * e1 + std::sin(ang) * e2;
          samples.push_back({c + r * nrm, nrm, id});
        }
      }
      carry = s - len;
    }
  }
  // A rectangle: corner o, edges ea, eb; normal ea x eb (both sides are drawn; the z-buffer picks).
  void add_rect(const Eigen::Vector3d& o, const Eigen::Vector3d& ea, const Eigen::Vector3d& eb, int id) {
    const Eigen::Vector3d n = ea.cross(eb).normalized();
    const int na = static_cast<int>(ea.norm() / spacing), nb = static_cast<int>(eb.norm() / spacing);
    for (int i = 0; i <= na; ++i)
      for (int j = 0; j <= nb; ++j) samples.push_back({o + ea * (double(i) / na) + eb * (double(j) / nb), n, id});
  }
  void add_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int id) {
    const Eigen::Vector3d d = hi - lo;
    const Eigen::Vector3d X(d.x(), 0, 0), Y(0, d.y(), 0), Z(0, 0, d.z());
    add_rect(lo, Y, X, id);
    add_rect(lo + Z, X, Y, id);
    add_rect(lo, X, Z, id);
    add_rect(lo + Y, Z, X, id);
    add_rect(lo, Z, Y, id);
    add_rect(lo + X, Y, Z, id);
  }
};

struct Scan {
  ewis::Cloud cloud;
  std::vector<int> label;  // object id per point, -1 for outliers
};

inline Scan render(const Scene& scene, double noise_mm = 0.2, double outlier_fraction = 0.4,
                   std::uint64_t seed = 7, double pixel_mm_at_600 = 0.5) {
  const double ang = pixel_mm_at_600 / 600.0;
  std::unordered_map<std::int64_t, std::pair<double, int>> zbuf;
  zbuf.reserve(scene.samples.size() / 4);
  for (int i = 0; i < static_cast<int>(scene.samples.size()); ++i) {
    const Sample& s = scene.samples[i];
    if (s.p.z() <= 1.0) continue;
    const std::int64_t u = static_cast<std::int64_t>(std::floor(s.p.x() / s.p.z() / ang));
    const std::int64_t v = static_cast<std::int64_t>(std::floor(s.p.y() / s.p.z() / ang));
    const std::int64_t key = (u + (1 << 20)) * (std::int64_t(1) << 22) + (v + (1 << 20));
    const double depth = s.p.norm();
    auto it = zbuf.find(key);
    if (it == zbuf.end()) zbuf.emplace(key, std::make_pair(depth, i));
    else if (depth < it->second.first) it->second = {depth, i};
  }
  std::vector<std::pair<std::int64_t, int>> pixels;
  pixels.reserve(zbuf.size());
  for (const auto& kv : zbuf) pixels.push_back({kv.first, kv.second.second});
  std::sort(pixels.begin(), pixels.end());
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_mm);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  Scan scan;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& px : pixels) {
    const Sample& s = scene.samples[px.second];
    const Eigen::Vector3d ray = s.p.normalized();
    const Eigen::Vector3d p = s.p + ray * noise(rng);
    scan.cloud.points.push_back(p.cast<float>());
    scan.label.push_back(s.id);
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const std::size_t surface = scan.cloud.points.size();
  const std::size_t outliers = static_cast<std::size_t>(surface * outlier_fraction / (1.0 - outlier_fraction));
  lo.array() -= 5.0;
  hi.array() += 5.0;
  std::size_t added = 0;
  while (added < outliers) {
    if (uni(rng) < 0.5) {
      // uniform in the scene's box
      const Eigen::Vector3d p(lo.x() + (hi.x() - lo.x()) * uni(rng), lo.y() + (hi.y() - lo.y()) * uni(rng),
                              lo.z() + (hi.z() - lo.z()) * uni(rng));
      scan.cloud.points.push_back(p.cast<float>());
      scan.label.push_back(-1);
      ++added;
    } else {
      // a flying-pixel cluster of 2-4 points along a ray through a surface point
      const Eigen::Vector3d base = scan.cloud.points[static_cast<std::size_t>(uni(rng) * surface) % surface].cast<double>();
      const double off = (uni(rng) < 0.5 ? -1 : 1) * (1.0 + 14.0 * uni(rng));
      const int k = 2 + static_cast<int>(uni(rng) * 3);
      for (int j = 0; j < k && added < outliers; ++j, ++added) {
        const Eigen::Vector3d p = base + base.normalized() * (off + 0.3 * noise(rng)) +
                                  Eigen::Vector3d(noise(rng), noise(rng), noise(rng)) * 1.5;
        scan.cloud.points.push_back(p.cast<float>());
        scan.label.push_back(-1);
      }
    }
  }
  return scan;
}

// Dense polylines for centrelines.
inline std::vector<Eigen::Vector3d> line(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double step = 0.5) {
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step)));
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i <= n; ++i) out.push_back(a + (b - a) * (double(i) / n));
  return out;
}
inline std::vector<Eigen::Vector3d> curve(const std::function<Eigen::Vector3d(double)>& f, double t0, double t1,
                                          int n) {
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i <= n; ++i) out.push_back(f(t0 + (t1 - t0) * i / n));
  return out;
}

// Distance from p to a polyline, and the polyline parameter (arc length) of the nearest point.
inline double distance_to_polyline(const std::vector<Eigen::Vector3d>& pl, const Eigen::Vector3d& p,
                                   double* arc = nullptr) {
  double best = std::numeric_limits<double>::infinity(), acc = 0, best_arc = 0;
  for (std::size_t i = 0; i + 1 < pl.size(); ++i) {
    const Eigen::Vector3d ab = pl[i + 1] - pl[i];
    const double l2 = ab.squaredNorm();
    const double t = l2 > 0 ? std::clamp((p - pl[i]).dot(ab) / l2, 0.0, 1.0) : 0.0;
    const double d = (p - pl[i] - ab * t).norm();
    if (d < best) {
      best = d;
      best_arc = acc + t * std::sqrt(l2);
    }
    acc += std::sqrt(l2);
  }
  if (arc) *arc = best_arc;
  return best;
}

}  // namespace synth
