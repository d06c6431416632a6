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

std::vector<Cylinder> bridge_short_breaks(
    const std::vector<Cylinder>& chain, double max_break_mm,
    const std::function<double(const Eigen::Vector3d&, const Eigen::Vector3d&)>& held_mm) {
  std::vector<Cylinder> out = chain;
  // Run ends: position, outward direction (away from the run), radius, run index. A run is a stretch of
  // segments joined end to start.
  struct End {
    Eigen::Vector3d at, out;
    double radius_mm;
    std::size_t run;
  };
  std::vector<End> ends;
  std::size_t run = 0;
  auto joined = [&](std::size_t i) { return i > 0 && (chain[i - 1].end - chain[i].start).norm() <= 1e-6; };
  // A run's direction at an end, from its axis over about 2 diameters back from the end (at most the run): the
  // last sub-cable alone is the least reliable (it ends where the data gave out, often beside the object that broke
  // the trace). Two chords, over the nearer and the farther half, give the direction and its change, extrapolated
  // to the end (a run along an arc keeps its curvature).
  auto outward = [&](std::size_t i, bool at_start) {
    const double baseline = 4.0 * chain[i].radius_mm;
    const Eigen::Vector3d tip = at_start ? chain[i].start : chain[i].end;
    std::size_t k = i;
    double walked = chain[k].length_mm();
    Eigen::Vector3d half = at_start ? chain[k].end : chain[k].start;
    bool half_set = walked >= 0.5 * baseline;
    while (walked < baseline) {
      if (at_start) {
        if (k + 1 >= chain.size() || !joined(k + 1)) break;
        ++k;
      } else {
        if (!joined(k)) break;
        --k;
      }
      walked += chain[k].length_mm();
      if (!half_set && walked >= 0.5 * baseline) {
        half = at_start ? chain[k].end : chain[k].start;
        half_set = true;
      }
    }
    const Eigen::Vector3d far = at_start ? chain[k].end : chain[k].start;
    const Eigen::Vector3d n1 = tip - half, n2 = half - far;
    if (n1.norm() < 1e-9) return Eigen::Vector3d(Eigen::Vector3d::UnitX());
    if (n2.norm() < 1e-9) return Eigen::Vector3d(n1.normalized());
    const Eigen::Vector3d c1 = n1.normalized(), c2 = n2.normalized();
    const Eigen::Vector3d t = c1 + (c1 - c2) * (n1.norm() / (n1.norm() + n2.norm()));
    return t.norm() > 1e-9 ? Eigen::Vector3d(t.normalized()) : c1;
  };
  for (std::size_t i = 0; i < chain.size(); ++i) {
    if (!joined(i)) {
      if (i > 0) ++run;
      ends.push_back({chain[i].start, outward(i, true), chain[i].radius_mm, run});
    }
    if (i + 1 == chain.size() || !joined(i + 1)) ends.push_back({chain[i].end, outward(i, false), chain[i].radius_mm, run});
  }
  // Two ends belong together when they face each other (each within 60 deg of the line to the other).
  auto facing = [&](std::size_t a, std::size_t b) {
    const Eigen::Vector3d ab = ends[b].at - ends[a].at;
    const double len = ab.norm();
    if (len > max_break_mm && !(held_mm && len - held_mm(ends[a].at, ends[b].at) <= max_break_mm)) return false;
    return len < 1e-9 || (ends[a].out.dot(ab) > 0.5 * len && ends[b].out.dot(-ab) > 0.5 * len);
  };
  auto nearest_other = [&](std::size_t a) {
    std::size_t best = ends.size();
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t b = 0; b < ends.size(); ++b) {
      if (ends[b].run == ends[a].run || !facing(a, b)) continue;
      const double d = (ends[b].at - ends[a].at).norm();
      if (d < best_d) {
        best_d = d;
        best = b;
      }
    }
    return best;
  };
  for (std::size_t a = 0; a < ends.size(); ++a) {
    const std::size_t b = nearest_other(a);
    if (b == ends.size() || b < a || nearest_other(b) != a) continue;  // mutual nearest, each pair once
    // A cubic Hermite curve leaving each end along its run (a cable in the break keeps its course), as
    // cylinders of at most about a radius' length, one run of its own.
    const Eigen::Vector3d p0 = ends[a].at, p1 = ends[b].at;
    const double len = (p1 - p0).norm();
    const Eigen::Vector3d m0 = ends[a].out * len, m1 = -ends[b].out * len;
    const double radius = 0.5 * (ends[a].radius_mm + ends[b].radius_mm);
    const int pieces = std::clamp(static_cast<int>(std::ceil(len / std::max(radius, 1e-3))), 1, 32);
    auto at = [&](double t) {
      const double t2 = t * t, t3 = t2 * t;
      return Eigen::Vector3d((2 * t3 - 3 * t2 + 1) * p0 + (t3 - 2 * t2 + t) * m0 + (-2 * t3 + 3 * t2) * p1 +
                             (t3 - t2) * m1);
    };
    for (int k = 0; k < pieces; ++k) {
      Cylinder c;
      c.start = at(double(k) / pieces);
      c.end = at(double(k + 1) / pieces);
      c.radius_mm = radius;
      out.push_back(c);
    }
  }
  return out;
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
