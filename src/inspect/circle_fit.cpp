#include "ewis/inspect/circle_fit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace ewis {
namespace {

double geometric_cost(const std::vector<Eigen::Vector2d>& pts, const Eigen::Vector2d& c, double r) {
  double s = 0;
  for (const auto& p : pts) {
    const double d = (p - c).norm() - r;
    s += d * d;
  }
  return s;
}

// Circle through three points; false when (nearly) collinear.
bool circle_through(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                    Eigen::Vector2d& center, double& radius) {
  const Eigen::Vector2d ab = b - a, ac = c - a;
  const double d = 2.0 * (ab.x() * ac.y() - ab.y() * ac.x());
  const double scale = ab.squaredNorm() * ac.squaredNorm();
  if (scale <= 0 || d * d < 1e-18 * scale) return false;
  const double ab2 = ab.squaredNorm(), ac2 = ac.squaredNorm();
  const Eigen::Vector2d off((ac.y() * ab2 - ab.y() * ac2) / d, (ab.x() * ac2 - ac.x() * ab2) / d);
  center = a + off;
  radius = off.norm();
  return std::isfinite(radius);
}

}  // namespace

Circle2d fit_circle_2d(const std::vector<Eigen::Vector2d>& pts) {
  Circle2d out;
  const std::size_t n = pts.size();
  if (n < 3) return out;
  // Centre the data for conditioning.
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : pts) mean += p;
  mean /= double(n);
  double scale = 0;
  for (const auto& p : pts) scale = std::max(scale, (p - mean).norm());
  if (!(scale > 0)) return out;
  // Kasa: x^2 + y^2 + D x + E y + F = 0 in least squares (normal equations, scaled coordinates).
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atb = Eigen::Vector3d::Zero();
  for (const auto& p : pts) {
    const Eigen::Vector2d q = (p - mean) / scale;
    const Eigen::Vector3d row(q.x(), q.y(), 1.0);
    ata += row * row.transpose();
    atb -= row * q.squaredNorm();
  }
  const Eigen::Vector3d sol = ata.ldlt().solve(atb);
  if (!sol.allFinite()) return out;
  Eigen::Vector2d c(-sol(0) / 2, -sol(1) / 2);
  const double r2 = c.squaredNorm() - sol(2);
  if (!(r2 > 0) || !std::isfinite(r2)) return out;
  double r = std::sqrt(r2);
  c = mean + c * scale;
  r *= scale;
  // Geometric refinement (Gauss-Newton with step halving): Kasa is biased on short arcs.
  double cost = geometric_cost(pts, c, r);
  for (int it = 0; it < 30; ++it) {
    Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
    Eigen::Vector3d jtr = Eigen::Vector3d::Zero();
    for (const auto& p : pts) {
      const Eigen::Vector2d d = p - c;
      const double dn = d.norm();
      if (dn <= 0) continue;
      const Eigen::Vector3d j(-d.x() / dn, -d.y() / dn, -1.0);
      const double res = dn - r;
      jtj += j * j.transpose();
      jtr += j * res;
    }
    const Eigen::Vector3d step = jtj.ldlt().solve(-jtr);
    if (!step.allFinite()) break;
    double t = 1.0;
    bool improved = false;
    for (int k = 0; k < 8; ++k, t *= 0.5) {
      const Eigen::Vector2d c2 = c + t * step.head<2>();
      const double r2n = r + t * step(2);
      if (r2n <= 0) continue;
      const double cost2 = geometric_cost(pts, c2, r2n);
      if (cost2 < cost) {
        c = c2;
        r = r2n;
        improved = cost - cost2 > 1e-14 * (1 + cost);
        cost = cost2;
        break;
      }
    }
    if (!improved) break;
  }
  out.ok = std::isfinite(r) && c.allFinite();
  {
    // Covariance of (a, b, r): s^2 (J^T J)^-1 with s^2 the residual variance (n - 3 degrees of freedom).
    Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
    for (const auto& p : pts) {
      const Eigen::Vector2d d = p - c;
      const double dn = d.norm();
      if (dn <= 0) continue;
      const Eigen::Vector3d j(-d.x() / dn, -d.y() / dn, -1.0);
      jtj += j * j.transpose();
    }
    const double s2 = n > 3 ? cost / double(n - 3) : cost;
    const Eigen::Matrix3d cov = jtj.inverse() * s2;
    out.radius_se_mm = cov(2, 2) > 0 && std::isfinite(cov(2, 2)) ? std::sqrt(cov(2, 2))
                                                                 : std::numeric_limits<double>::infinity();
  }
  out.center = c;
  out.radius_mm = r;
  out.rms_mm = std::sqrt(cost / double(n));
  return out;
}

Circle3d fit_circle_3d(const Eigen::Vector3d* pts, std::size_t n) {
  Circle3d out;
  if (n < 3) return out;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) mean += pts[i];
  mean /= double(n);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d d = pts[i] - mean;
    cov += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Eigen::Vector3d normal = eig.eigenvectors().col(0);
  const Eigen::Vector3d e1 = eig.eigenvectors().col(2);
  const Eigen::Vector3d e2 = normal.cross(e1).normalized();
  std::vector<Eigen::Vector2d> q(n);
  double off2 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d d = pts[i] - mean;
    q[i] = {d.dot(e1), d.dot(e2)};
    const double z = d.dot(normal);
    off2 += z * z;
  }
  const Circle2d c2 = fit_circle_2d(q);
  // The line through the centroid along the major axis: the limit of circles of growing radius.
  const Eigen::Vector3d ev = eig.eigenvalues().cwiseMax(0.0);
  const double line_rms = std::sqrt((ev(0) + ev(1)) / double(n));
  out.ok = true;
  out.normal = normal;
  out.direction = e1;
  if (!c2.ok || !(c2.radius_mm < 1e12) || std::sqrt(c2.rms_mm * c2.rms_mm + off2 / double(n)) >= line_rms) {
    out.straight = true;
    out.center = mean;
    out.radius_mm = std::numeric_limits<double>::infinity();
    out.radius_se_mm = std::numeric_limits<double>::infinity();
    out.rms_mm = line_rms;
    return out;
  }
  out.center = mean + c2.center.x() * e1 + c2.center.y() * e2;
  out.radius_mm = c2.radius_mm;
  out.radius_se_mm = c2.radius_se_mm;
  out.rms_mm = std::sqrt(c2.rms_mm * c2.rms_mm + off2 / double(n));
  return out;
}

double circle_distance(const Circle3d& c, const Eigen::Vector3d& p, double* radial) {
  const Eigen::Vector3d d = p - c.center;
  const double z = d.dot(c.normal);
  if (c.straight) {
    const double along = d.dot(c.direction);
    const double in_plane = (d - z * c.normal - along * c.direction).norm();
    if (radial) *radial = in_plane;
    return std::sqrt(in_plane * in_plane + z * z);
  }
  const double e = (d - z * c.normal).norm() - c.radius_mm;
  if (radial) *radial = e;
  return std::sqrt(e * e + z * z);
}

RansacCircleResult ransac_circle_2d(const std::vector<Eigen::Vector2d>& pts, const RansacCircleParams& params) {
  RansacCircleResult out;
  const std::size_t n = pts.size();
  if (n < 3) return out;
  std::mt19937_64 rng(params.seed);
  std::uniform_int_distribution<std::size_t> pick(0, n - 1);
  std::size_t best_count = 0;
  double best_cost = 0;
  Eigen::Vector2d best_c = Eigen::Vector2d::Zero();
  double best_r = 0;
  const int iterations = std::max(1, params.iterations);
  for (int it = 0; it < iterations; ++it) {
    const std::size_t i = pick(rng), j = pick(rng), k = pick(rng);
    if (i == j || j == k || i == k) continue;
    Eigen::Vector2d c;
    double r;
    if (!circle_through(pts[i], pts[j], pts[k], c, r)) continue;
    if (r < params.min_radius_mm || r > params.max_radius_mm) continue;
    std::size_t count = 0;
    double cost = 0;
    for (const auto& p : pts) {
      const double d = std::abs((p - c).norm() - r);
      if (d <= params.inlier_mm) {
        ++count;
        cost += d * d;
      }
    }
    // More inliers wins; ties by the smaller residual (deterministic order of hypotheses).
    if (count > best_count || (count == best_count && count > 0 && cost < best_cost)) {
      best_count = count;
      best_cost = cost;
      best_c = c;
      best_r = r;
    }
  }
  if (best_count < 3) return out;
  std::vector<Eigen::Vector2d> in;
  for (std::size_t i = 0; i < n; ++i)
    if (std::abs((pts[i] - best_c).norm() - best_r) <= params.inlier_mm) {
      out.inliers.push_back(static_cast<std::uint32_t>(i));
      in.push_back(pts[i]);
    }
  out.circle = fit_circle_2d(in);
  if (!out.circle.ok || out.circle.radius_mm > params.max_radius_mm) {
    out.circle.ok = true;
    out.circle.center = best_c;
    out.circle.radius_mm = best_r;
    out.circle.rms_mm = std::sqrt(best_cost / double(best_count));
  }
  return out;
}

}  // namespace ewis
