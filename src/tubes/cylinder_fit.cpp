// paper 4.2.3: the sub-cable's radius and axis. The paper's mean distance to the axis is biased low by
// outliers inside the tube and by the partial arc a sensor sees (DESIGN.md "Measurement lessons"), so the
// cylinder is fitted by trimmed least squares (Gauss-Newton on axis point, direction and radius).
#include "ewis/tubes/cylinder_fit.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "ewis/core/robust.hpp"
#include "ewis/tubes/directions.hpp"

namespace ewis {
namespace {

constexpr double kSparseArcMaxDeg = 200.0;  // see sparse_arc_extent_deg

// Angular extent of the points around the axis (angles in [0, 2 pi)): 10-degree sectors holding a fair
// share of the points. Robust to the few outliers that pass the trimming on the far side of the axis.
double arc_extent_deg(const int (&bins)[36]) {
  const int peak = *std::max_element(bins, bins + 36);
  if (peak == 0) return 0.0;
  const int need = std::max(2, peak / 5);
  int occupied = 0;
  for (int i = 0; i < 36; ++i) occupied += bins[i] >= need;
  return occupied * 10.0;
}

// The same for a sparse fit (fewer than kSparseFitInliers): a thin tube in a sparse scan shows
// 3-5 pixel columns across, each at one angle, so 10 deg sectors of 2 points read a 100 deg arc as 40-70
// deg. Here the extent is the angular range of the points around their mean direction, without the outer
// 5 % on each side, when that is at most kSparseArcMaxDeg: one view sees at most half a tube, and a few
// points spread further round an axis are scattered points (a noisy plane with outliers), not a tube's seen
// side; those keep the sector count.
double sparse_arc_extent_deg(std::vector<double>& angles) {
  if (angles.size() < 2) return 0.0;
  double sx = 0, sy = 0;
  for (double a : angles) sx += std::cos(a), sy += std::sin(a);
  const double mean = std::atan2(sy, sx);
  for (double& a : angles) a = std::remainder(a - mean, 2 * M_PI);
  std::sort(angles.begin(), angles.end());
  const std::size_t trim = angles.size() / 20;
  const double extent = (angles[angles.size() - 1 - trim] - angles[trim]) * 180.0 / M_PI;
  return extent <= kSparseArcMaxDeg ? extent : 0.0;
}

// A sensor sees only the side of a tube that faces it: points on the far side of the axis are outliers
// (flying pixels, noise inside the tube) that would let the axis slide and the radius shrink on a partial
// arc (DESIGN.md "Measurement lessons"). With the sensor position: back-facing points go; without it: points
// more than ~100 deg from the mean direction of the seen arc go (nothing when the arc is nearly closed, as
// in scans from all sides). `radial` holds each point's unit direction from the axis. Returns the inlier count.
int drop_far_side(const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& radial,
                  const CylinderFitParams& params, std::vector<char>& inl) {
  const std::size_t n = points.size();
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  int count = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (inl[i]) {
      mean += radial[i];
      ++count;
    }
  if (count == 0) return 0;
  mean /= count;
  const bool by_mean = mean.norm() > 0.35;
  const Eigen::Vector3d m = by_mean ? Eigen::Vector3d(mean.normalized()) : Eigen::Vector3d::Zero();
  count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!inl[i]) continue;
    if (params.use_sensor) {
      if (radial[i].dot(params.sensor - points[i]) < 0) inl[i] = 0;
    } else if (by_mean && radial[i].dot(m) < -0.2) {
      inl[i] = 0;
    }
    count += inl[i];
  }
  return count;
}

// Residuals (distance to the surface) and unit radial directions of all points for the cylinder (c, u, rho).
void residuals(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& c, const Eigen::Vector3d& u,
               double rho, std::vector<double>& resid, std::vector<Eigen::Vector3d>& radial) {
  const std::size_t n = points.size();
  resid.resize(n);
  radial.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d q = points[i] - c;
    const Eigen::Vector3d rq = q - u * u.dot(q);
    const double len = rq.norm();
    resid[i] = len - rho;
    radial[i] = len > 1e-12 ? Eigen::Vector3d(rq / len) : Eigen::Vector3d::Zero();
  }
}

// The trimmed Gauss-Newton rounds on `points`; updates (c, u, rho). False when the fit breaks down.
bool gauss_newton_rounds(const std::vector<Eigen::Vector3d>& points, const CylinderFitParams& params,
                         Eigen::Vector3d& c, Eigen::Vector3d& u, double& rho) {
  const std::size_t n = points.size();
  std::vector<char> inl(n, 1);
  std::vector<double> resid, tmp;
  std::vector<Eigen::Vector3d> radial;
  const int np = params.fix_radius ? 4 : 5;
  for (int round = 0; round < std::max(params.rounds, 1); ++round) {
    // trimming: inliers from the current model's residuals (paper's "empty space around cables")
    residuals(points, c, u, rho, resid, radial);
    double med = 0, sigma = 0;
    median_and_robust_sigma(resid, params.min_sigma_mm, tmp, med, sigma);
    for (std::size_t i = 0; i < n; ++i) inl[i] = std::abs(resid[i] - med) <= params.trim_sigmas * sigma;
    const int count = drop_far_side(points, radial, params, inl);
    if (count < 6) return false;
    for (int it = 0; it < params.iterations; ++it) {
      // keep the axis point central along the axis: better conditioned tilt updates
      double zsum = 0;
      for (std::size_t i = 0; i < n; ++i)
        if (inl[i]) zsum += u.dot(points[i] - c);
      c += u * (zsum / count);
      const Eigen::Matrix3d frame = rotation_from_z(u);
      const Eigen::Vector3d e1 = frame.col(0), e2 = frame.col(1);
      Eigen::Matrix<double, 5, 5> A = Eigen::Matrix<double, 5, 5>::Zero();
      Eigen::Matrix<double, 5, 1> b = Eigen::Matrix<double, 5, 1>::Zero();
      for (std::size_t i = 0; i < n; ++i) {
        if (!inl[i]) continue;
        const Eigen::Vector3d q = points[i] - c;
        const double x = q.dot(e1), y = q.dot(e2), z = q.dot(u);
        const double d = std::sqrt(x * x + y * y);  // not std::hypot: a library call per point, 3x slower
        if (d < 1e-12) continue;
        const double nx = x / d, ny = y / d;
        double s = 1.0;
        if (params.use_sensor) {
          // residual along the camera ray: surface distance / cos(angle between ray and normal)
          const Eigen::Vector3d v = (points[i] - params.sensor).normalized();
          s = 1.0 / std::max(std::abs(v.dot(nx * e1 + ny * e2)), 0.3);
        }
        Eigen::Matrix<double, 5, 1> J;
        J << -nx * s, -ny * s, -nx * z * s, -ny * z * s, -s;
        const double e = s * (d - rho);
        A.noalias() += J * J.transpose();  // a fixed 5x5 outer product, inlined (rankUpdate: a library call)
        b -= J * e;
      }
      A.diagonal().array() += 1e-9 * (A.trace() + 1.0);
      Eigen::Matrix<double, 5, 1> delta = Eigen::Matrix<double, 5, 1>::Zero();
      delta.head(np) = A.topLeftCorner(np, np).ldlt().solve(b.head(np));
      if (!delta.allFinite()) return false;
      c += delta[0] * e1 + delta[1] * e2;
      u = (u + delta[2] * e1 + delta[3] * e2).normalized();
      if (!params.fix_radius) rho += delta[4];
      if (!(rho > 0) || rho > params.max_radius_mm) return false;
      // converged well below the noise (1e-6 mm, 1e-6 rad): further iterations change nothing measurable
      if (delta.head(4).norm() < 1e-6 && std::abs(delta[4]) < 1e-6) break;
    }
  }
  return true;
}

}  // namespace

CylinderFitResult fit_cylinder(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& point,
                               const Eigen::Vector3d& axis, double radius_mm, const CylinderFitParams& params) {
  CylinderFitResult res;
  const std::size_t n = points.size();
  if (n < 6 || !(radius_mm > 0) || !(axis.norm() > 0)) return res;
  Eigen::Vector3d c = point;
  Eigen::Vector3d u = axis.normalized();
  const Eigen::Vector3d u0 = u;
  double rho = radius_mm;
  // dense data: the rounds on an evenly strided subset (a few hundred points fix five parameters far below
  // the noise); the inliers and the quality below are still measured on all points
  const std::size_t cap = params.max_points > 0 ? static_cast<std::size_t>(std::max(params.max_points, 32)) : n;
  if (n > cap) {
    const std::size_t stride = (n + cap - 1) / cap;
    std::vector<Eigen::Vector3d> sub;
    sub.reserve(n / stride + 1);
    for (std::size_t i = 0; i < n; i += stride) sub.push_back(points[i]);
    if (!gauss_newton_rounds(sub, params, c, u, rho)) return res;
  } else if (!gauss_newton_rounds(points, params, c, u, rho)) {
    return res;
  }
  // final inliers and quality
  std::vector<double> resid;
  std::vector<Eigen::Vector3d> radial;
  residuals(points, c, u, rho, resid, radial);
  const double sigma = robust_sigma(resid, params.min_sigma_mm);
  std::vector<char> inl(n);
  for (std::size_t i = 0; i < n; ++i) inl[i] = std::abs(resid[i]) <= params.trim_sigmas * sigma;
  drop_far_side(points, radial, params, inl);
  const Eigen::Matrix3d frame = rotation_from_z(u);
  int bins[36] = {0};
  double ss = 0;
  int count = 0;
  std::vector<double> angles;
  for (std::size_t i = 0; i < n; ++i) {
    if (!inl[i]) continue;
    ++count;
    ss += resid[i] * resid[i];
    const double a = std::atan2(radial[i].dot(frame.col(1)), radial[i].dot(frame.col(0))) + M_PI;
    bins[std::clamp(static_cast<int>(a / (2 * M_PI) * 36.0), 0, 35)]++;
    if (angles.size() < static_cast<std::size_t>(kSparseFitInliers)) angles.push_back(a);
  }
  if (count < 6) return res;
  if (u.dot(u0) < 0) u = -u;
  res.ok = true;
  res.axis = u;
  res.point = c + u * u.dot(point - c);
  res.radius_mm = rho;
  res.rms_mm = std::sqrt(ss / count);
  res.inliers = count;
  res.arc_deg = count < 2                   ? 0.0
                : count < kSparseFitInliers ? std::max(arc_extent_deg(bins), sparse_arc_extent_deg(angles))
                                            : arc_extent_deg(bins);
  res.inlier = std::move(inl);
  return res;
}

CircleFitResult fit_circle(const std::vector<Eigen::Vector2d>& pts, double trim_sigmas, double min_sigma_mm) {
  CircleFitResult res;
  const std::size_t n = pts.size();
  if (n < 3) return res;
  // Kasa: x^2 + y^2 + D x + E y + F = 0, linear least squares (centred for conditioning)
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : pts) mean += p;
  mean /= static_cast<double>(n);
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const auto& p0 : pts) {
    const Eigen::Vector2d p = p0 - mean;
    const Eigen::Vector3d row(p.x(), p.y(), 1.0);
    A += row * row.transpose();
    b -= row * p.squaredNorm();
  }
  const Eigen::Vector3d sol = A.ldlt().solve(b);
  Eigen::Vector2d c(-sol[0] / 2, -sol[1] / 2);
  double r2 = c.squaredNorm() - sol[2];
  if (!sol.allFinite() || !(r2 > 0)) return res;
  double r = std::sqrt(r2);
  c += mean;
  std::vector<double> resid(n);
  std::vector<char> inl(n, 1);
  for (int round = 0; round < 3; ++round) {
    for (std::size_t i = 0; i < n; ++i) resid[i] = (pts[i] - c).norm() - r;
    const double sigma = robust_sigma(resid, min_sigma_mm);
    int count = 0;
    for (std::size_t i = 0; i < n; ++i) count += inl[i] = std::abs(resid[i]) <= trim_sigmas * sigma;
    if (count < 3) return res;
    for (int it = 0; it < 8; ++it) {
      Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
      Eigen::Vector3d g = Eigen::Vector3d::Zero();
      for (std::size_t i = 0; i < n; ++i) {
        if (!inl[i]) continue;
        const Eigen::Vector2d q = pts[i] - c;
        const double d = q.norm();
        if (d < 1e-12) continue;
        const Eigen::Vector3d J(-q.x() / d, -q.y() / d, -1.0);
        H += J * J.transpose();
        g -= J * (d - r);
      }
      H.diagonal().array() += 1e-9 * (H.trace() + 1.0);
      const Eigen::Vector3d delta = H.ldlt().solve(g);
      if (!delta.allFinite()) return res;
      c += delta.head<2>();
      r += delta[2];
      if (!(r > 0)) return res;
      if (delta.norm() < 1e-9) break;
    }
  }
  double ss = 0;
  int count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double e = (pts[i] - c).norm() - r;
    if (!inl[i]) continue;
    ss += e * e;
    ++count;
  }
  res.ok = count >= 3;
  res.center = c;
  res.radius_mm = r;
  res.rms_mm = count ? std::sqrt(ss / count) : 0.0;
  res.inliers = count;
  return res;
}

}  // namespace ewis
