#include "ewis/inspect/chain_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ewis {

ChainPoint distance_to_chain(const std::vector<Cylinder>& chain, const Eigen::Vector3d& p) {
  ChainPoint best;
  best.distance_mm = std::numeric_limits<double>::infinity();
  double best_raw_t = 0;
  for (std::size_t i = 0; i < chain.size(); ++i) {
    const Eigen::Vector3d ab = chain[i].end - chain[i].start;
    const double len2 = ab.squaredNorm();
    const double raw = len2 > 0 ? (p - chain[i].start).dot(ab) / len2 : 0.0;
    const double t = std::clamp(raw, 0.0, 1.0);
    const double d = (p - (chain[i].start + t * ab)).norm();
    if (d < best.distance_mm) {
      best.distance_mm = d;
      best.segment = i;
      best.t = t;
      best_raw_t = raw;
    }
  }
  if (!chain.empty()) {
    // A chain may hold several runs end to end (a cable traced on both sides of a clamp): a run starts where
    // a segment does not begin at its predecessor's end.
    const std::size_t i = best.segment;
    const bool run_start = i == 0 || (chain[i - 1].end - chain[i].start).norm() > 1e-6;
    const bool run_end = i + 1 == chain.size() || (chain[i + 1].start - chain[i].end).norm() > 1e-6;
    best.beyond_end = (run_start && best_raw_t < 0) || (run_end && best_raw_t > 1);
  }
  return best;
}

double segment_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                        const Eigen::Vector3d& q1, Eigen::Vector3d* on_p, Eigen::Vector3d* on_q) {
  // Ericson 5.1.9, with the degenerate cases.
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  const double eps = 1e-12;
  if (a <= eps && e <= eps) {
    s = t = 0;
  } else if (a <= eps) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= eps) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > eps * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  const Eigen::Vector3d cp = p0 + d1 * s, cq = q0 + d2 * t;
  if (on_p) *on_p = cp;
  if (on_q) *on_q = cq;
  return (cp - cq).norm();
}

double chain_distance(const std::vector<Cylinder>& a, const std::vector<Cylinder>& b, Eigen::Vector3d* on_a,
                      Eigen::Vector3d* on_b) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& x : a)
    for (const auto& y : b) {
      Eigen::Vector3d pa, pb;
      const double d = segment_distance(x.start, x.end, y.start, y.end, &pa, &pb);
      if (d < best) {
        best = d;
        if (on_a) *on_a = pa;
        if (on_b) *on_b = pb;
      }
    }
  return best;
}

}  // namespace ewis
