// paper 4.2 output: the chain's measured radius, a smooth centreline through its joints, and the set S of
// scan points that belong to the tube (paper 4.3.2); plus helpers on a finished chain.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "tube_internal.hpp"

namespace ewis {
namespace tubes_detail {
namespace {

// Centripetal Catmull-Rom between p1 and p2 (p0, p3 the neighbours): follows circles closely, no loops.
Eigen::Vector3d catmull_rom(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                            const Eigen::Vector3d& p3, double s) {
  auto knot = [](double t, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return t + std::max(std::sqrt((b - a).norm()), 1e-9);
  };
  const double t0 = 0, t1 = knot(t0, p0, p1), t2 = knot(t1, p1, p2), t3 = knot(t2, p2, p3);
  const double t = t1 + s * (t2 - t1);
  const Eigen::Vector3d a1 = (t1 - t) / (t1 - t0) * p0 + (t - t0) / (t1 - t0) * p1;
  const Eigen::Vector3d a2 = (t2 - t) / (t2 - t1) * p1 + (t - t1) / (t2 - t1) * p2;
  const Eigen::Vector3d a3 = (t3 - t) / (t3 - t2) * p2 + (t - t2) / (t3 - t2) * p3;
  const Eigen::Vector3d b1 = (t2 - t) / (t2 - t0) * a1 + (t - t0) / (t2 - t0) * a2;
  const Eigen::Vector3d b2 = (t3 - t) / (t3 - t1) * a2 + (t - t1) / (t3 - t1) * a3;
  return (t2 - t) / (t2 - t1) * b1 + (t - t1) / (t2 - t1) * b2;
}

std::vector<Eigen::Vector3d> smooth_centerline(const std::vector<Eigen::Vector3d>& joints, double spacing) {
  std::vector<Eigen::Vector3d> out;
  const std::size_t n = joints.size();
  if (n == 0) return out;
  out.push_back(joints[0]);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const Eigen::Vector3d& p1 = joints[i];
    const Eigen::Vector3d& p2 = joints[i + 1];
    const Eigen::Vector3d p0 = i > 0 ? joints[i - 1] : 2 * p1 - p2;
    const Eigen::Vector3d p3 = i + 2 < n ? joints[i + 2] : 2 * p2 - p1;
    const double len = (p2 - p1).norm();
    const int m = std::clamp(static_cast<int>(std::ceil(len / spacing)), 1, 10000);
    for (int k = 1; k <= m; ++k) {
      if (len < 1e-9) break;
      out.push_back(k == m ? p2 : catmull_rom(p0, p1, p2, p3, static_cast<double>(k) / m));
    }
  }
  return out;
}

}  // namespace

void finish_trace(Context& ctx, TubeTrace& t) {
  std::vector<double> radii, rms;
  for (const SubCable& s : t.segments)
    if (!s.bridged) {
      radii.push_back(s.cylinder.radius_mm);
      rms.push_back(s.rms_mm);
    }
  auto med = [](std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  // robust over the chain: single windows are noisy, the median is not
  t.radius_mm = med(radii);
  t.rms_mm = med(rms);
  std::vector<Eigen::Vector3d> joints;
  joints.push_back(t.segments.front().cylinder.start);
  for (const SubCable& s : t.segments) joints.push_back(s.cylinder.end);
  t.centerline = smooth_centerline(joints, std::max(0.5 * t.radius_mm, 1e-3));
  t.length_mm = polyline_length(t.centerline);
  // the set S: scan points within radius + tolerance of the fitted chain; the chain's ends (and the sides
  // of a gap) are cut flat, joints inside are rounded so that bends leave no wedge uncovered
  const double tol = ctx.tolerance_mm;
  std::vector<std::uint32_t> all;
  std::vector<Eigen::Vector3d> rel;
  std::vector<std::uint32_t> ids;
  const std::size_t n = t.segments.size();
  for (std::size_t i = 0; i < n; ++i) {
    SubCable& s = t.segments[i];
    if (s.bridged) continue;
    const bool open_start = i == 0 || t.segments[i - 1].bridged;
    const bool open_end = i + 1 == n || t.segments[i + 1].bridged;
    const Eigen::Vector3d a = s.cylinder.start, b = s.cylinder.end;
    const double len = (b - a).norm();
    const double rr = s.cylinder.radius_mm + tol;
    gather(ctx, 0.5 * (a + b), std::sqrt(0.25 * len * len + rr * rr) + 1e-6, a, rel, &ids);
    const Eigen::Vector3d ab = b - a;
    const double len2 = std::max(ab.squaredNorm(), 1e-18);
    std::uint32_t count = 0;
    for (std::size_t k = 0; k < rel.size(); ++k) {
      double u = rel[k].dot(ab) / len2;
      if ((open_start && u < 0) || (open_end && u > 1)) continue;
      u = std::clamp(u, 0.0, 1.0);
      if ((rel[k] - ab * u).squaredNorm() <= rr * rr) {
        all.push_back(ids[k]);
        ++count;
      }
    }
    s.points = count;
  }
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  t.points = std::move(all);
}

}  // namespace tubes_detail

double polyline_length(const std::vector<Eigen::Vector3d>& polyline) {
  double len = 0;
  for (std::size_t i = 1; i < polyline.size(); ++i) len += (polyline[i] - polyline[i - 1]).norm();
  return len;
}

double run_support(const TubeTrace& trace, const Eigen::Vector3d& sensor, double resolution_mm) {
  double shown_mm2 = 0.0;
  for (const SubCable& s : trace.segments) {
    if (s.bridged) continue;
    const Eigen::Vector3d ray = (sensor - 0.5 * (s.cylinder.start + s.cylinder.end)).normalized();
    shown_mm2 += 2.0 * trace.radius_mm * s.cylinder.axis().cross(ray).norm() * s.cylinder.length_mm();
  }
  const double expected = shown_mm2 / (resolution_mm * resolution_mm);
  return expected > 0 ? double(trace.points.size()) / expected : 0.0;
}

double distance_to_chain(const TubeTrace& trace, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const SubCable& s : trace.segments) best = std::min(best, distance_to_segment(s.cylinder, p));
  return best;
}

double chain_coverage(const TubeTrace& trace, const std::vector<Eigen::Vector3d>& reference, double tolerance_mm) {
  double total = 0, covered = 0;
  for (std::size_t i = 1; i < reference.size(); ++i) {
    const Eigen::Vector3d a = reference[i - 1], b = reference[i];
    const double len = (b - a).norm();
    const int m = std::clamp(static_cast<int>(std::ceil(len / 0.5)), 1, 100000);
    for (int k = 0; k < m; ++k) {
      const Eigen::Vector3d mid = a + (b - a) * ((k + 0.5) / m);
      total += len / m;
      if (distance_to_chain(trace, mid) <= tolerance_mm) covered += len / m;
    }
  }
  return total > 0 ? covered / total : 0.0;
}

}  // namespace ewis
