// Smooth tube (quartic centreline over a chord) fit to a bent tube's surface points (see smooth_tube_fit.hpp).
#include "ewis/inspect/smooth_tube_fit.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "ewis/core/cloud.hpp"
#include "ewis/core/robust.hpp"

namespace ewis {
namespace {

constexpr int kDegree = 4;
constexpr int kCoefficients = kDegree + 1;
constexpr int kParams = 2 * kCoefficients + 1;  // f (5), g (5), tube radius
using Vec = Eigen::Matrix<double, kParams, 1>;
using Mat = Eigen::Matrix<double, kParams, kParams>;
using Coefficients = std::array<double, kCoefficients>;

struct PolyValue {
  double value = 0, d1 = 0, d2 = 0;
};

// Horner's scheme with the first two derivatives.
PolyValue eval(const Coefficients& c, double x) {
  PolyValue p;
  for (int k = kDegree; k >= 0; --k) {
    p.d2 = p.d2 * x + 2.0 * p.d1;
    p.d1 = p.d1 * x + p.value;
    p.value = p.value * x + c[std::size_t(k)];
  }
  return p;
}

struct CurvePoint {
  Eigen::Vector3d c, d1, d2;  // point and derivatives in tau
};

CurvePoint curve_at(const SmoothTubeModel& m, double tau) {
  const PolyValue f = eval(m.f, tau), g = eval(m.g, tau);
  CurvePoint q;
  q.c = m.origin + m.half_chord_mm * tau * m.u + f.value * m.v + g.value * m.w;
  q.d1 = m.half_chord_mm * m.u + f.d1 * m.v + g.d1 * m.w;
  q.d2 = f.d2 * m.v + g.d2 * m.w;
  return q;
}

double curvature_of(const CurvePoint& q) {
  const double n = q.d1.norm();
  return n > 0 ? q.d1.cross(q.d2).norm() / (n * n * n) : 0.0;
}

// Closest point's parameter by Newton steps on |p - c(tau)|^2 from tau (nan: from p's projection on the chord).
double closest_tau(const SmoothTubeModel& m, const Eigen::Vector3d& p, double tau) {
  tau = std::clamp(std::isfinite(tau) ? tau : m.tau_of(p), -1.5, 1.5);
  for (int it = 0; it < 6; ++it) {
    const CurvePoint q = curve_at(m, tau);
    const Eigen::Vector3d d = p - q.c;
    const double g = -d.dot(q.d1);
    double h = q.d1.squaredNorm() - d.dot(q.d2);
    if (!(h > 1e-12)) h = q.d1.squaredNorm();
    const double step = std::clamp(-g / h, -0.25, 0.25);
    tau = std::clamp(tau + step, -1.5, 1.5);
    if (std::abs(step) < 1e-10) break;
  }
  return tau;
}

SmoothTubeModel apply(const SmoothTubeModel& base, const Vec& x) {
  SmoothTubeModel m = base;
  for (int k = 0; k < kCoefficients; ++k) {
    m.f[std::size_t(k)] += x[k];
    m.g[std::size_t(k)] += x[kCoefficients + k];
  }
  m.tube_radius_mm += x[kParams - 1];
  return m;
}

// The points over the chord (projection within [-1, 1]), evenly strided down to max_points.
std::vector<Eigen::Vector3d> points_over_chord(const std::vector<Eigen::Vector3d>& points, const SmoothTubeModel& m,
                                               std::size_t max_points) {
  std::vector<Eigen::Vector3d> over;
  for (const Eigen::Vector3d& p : points)
    if (m.over_chord(p)) over.push_back(p);
  return pick(over, evenly_strided(over.size(), max_points));
}

}  // namespace

Eigen::Vector3d SmoothTubeModel::point(double tau) const { return curve_at(*this, tau).c; }

double SmoothTubeModel::curvature(double tau) const { return curvature_of(curve_at(*this, tau)); }

double SmoothTubeModel::tau_of(const Eigen::Vector3d& p) const { return u.dot(p - origin) / half_chord_mm; }

bool SmoothTubeModel::over_chord(const Eigen::Vector3d& p) const {
  const double tau = tau_of(p);
  return tau >= -1.0 && tau <= 1.0;
}

double smooth_tube_centreline_distance(const SmoothTubeModel& m, const Eigen::Vector3d& p, double* tau_io) {
  const double tau = closest_tau(m, p, tau_io ? *tau_io : std::numeric_limits<double>::quiet_NaN());
  if (tau_io) *tau_io = tau;
  return (p - curve_at(m, tau).c).norm();
}

double smooth_tube_robust_cost(const std::vector<Eigen::Vector3d>& points, const SmoothTubeModel& model,
                               double scale_mm) {
  double s = 0;
  for (const Eigen::Vector3d& p : points)
    s += cauchy_rho(smooth_tube_centreline_distance(model, p) - model.tube_radius_mm, scale_mm);
  return s;
}

SmoothTubeFit fit_smooth_tube(const std::vector<Eigen::Vector3d>& surface_points,
                              const std::vector<Eigen::Vector3d>& centreline, const Eigen::Vector3d& a,
                              const Eigen::Vector3d& b, double tube_radius_mm, const SmoothTubeFitParams& params) {
  SmoothTubeModel m;
  const Eigen::Vector3d chord = b - a;
  if (!(chord.norm() > 0) || !(tube_radius_mm > 0)) return {};
  m.origin = 0.5 * (a + b);
  m.half_chord_mm = 0.5 * chord.norm();
  m.u = chord.normalized();
  m.v = m.u.unitOrthogonal();
  m.w = m.u.cross(m.v);
  m.tube_radius_mm = tube_radius_mm;
  // The initial curve: least-squares quartics through the centreline samples over the chord (a light ridge keeps
  // a window with few samples well posed; the chord's ends are samples too).
  Eigen::Matrix<double, kCoefficients, kCoefficients> A = Eigen::Matrix<double, kCoefficients, kCoefficients>::Zero();
  Eigen::Matrix<double, kCoefficients, 2> rhs = Eigen::Matrix<double, kCoefficients, 2>::Zero();
  auto add = [&](const Eigen::Vector3d& c) {
    const Eigen::Vector3d d = c - m.origin;
    const double tau = m.tau_of(c);
    if (tau < -1.0 - 1e-9 || tau > 1.0 + 1e-9) return;
    Eigen::Matrix<double, kCoefficients, 1> row;
    double pw = 1.0;
    for (int k = 0; k < kCoefficients; ++k, pw *= tau) row[k] = pw;
    A += row * row.transpose();
    rhs.col(0) += row * m.v.dot(d);
    rhs.col(1) += row * m.w.dot(d);
  };
  add(a);
  add(b);
  for (const Eigen::Vector3d& c : centreline) add(c);
  for (int k = 0; k < kCoefficients; ++k) A(k, k) += 1e-6 * (1.0 + A(0, 0));
  const Eigen::Matrix<double, kCoefficients, 2> coef = A.ldlt().solve(rhs);
  if (!coef.allFinite()) return {};
  for (int k = 0; k < kCoefficients; ++k) {
    m.f[std::size_t(k)] = coef(k, 0);
    m.g[std::size_t(k)] = coef(k, 1);
  }
  return fit_smooth_tube_from(surface_points, m, params);
}

SmoothTubeFit fit_smooth_tube_from(const std::vector<Eigen::Vector3d>& surface_points, const SmoothTubeModel& initial,
                                   const SmoothTubeFitParams& params) {
  SmoothTubeFit out;
  out.model = initial;
  if (!(initial.half_chord_mm > 0) || !(initial.tube_radius_mm > 0)) return out;
  const std::vector<Eigen::Vector3d> pts = points_over_chord(surface_points, initial, params.max_points);
  const std::size_t n = pts.size();
  out.points = n;
  if (n < 5 * kParams) return out;

  SmoothTubeModel model = initial;
  std::vector<double> res(n), trial_res(n), tau(n), trial_tau(n), tmp;
  std::vector<Eigen::Vector3d> normal(n), trial_normal(n);
  for (std::size_t i = 0; i < n; ++i) tau[i] = std::numeric_limits<double>::quiet_NaN();
  // Residuals (distance to the centreline less the tube radius), closest parameters and unit normals.
  auto residuals = [&](const SmoothTubeModel& mm, std::vector<double>& r, std::vector<double>& t,
                       std::vector<Eigen::Vector3d>& nrm) {
    for (std::size_t i = 0; i < n; ++i) {
      t[i] = closest_tau(mm, pts[i], tau[i]);
      const Eigen::Vector3d dir = pts[i] - curve_at(mm, t[i]).c;
      const double d = dir.norm();
      r[i] = d - mm.tube_radius_mm;
      nrm[i] = d > 0 ? Eigen::Vector3d(dir / d) : Eigen::Vector3d::Zero();
    }
  };
  auto sigma_of = [&](const std::vector<double>& r) { return robust_sigma(r, params.min_noise_mm, tmp); };
  auto cost_of = [&](const std::vector<double>& r, double c) {
    double s = 0;
    for (double v : r) s += cauchy_rho(v, c);
    return s;
  };
  // The Cauchy-weighted normal equations: at the closest point the distance's gradient in a coefficient is the
  // curve's shift along the normal (the closest parameter is stationary).
  struct Normal {
    Mat H = Mat::Zero();
    Vec g = Vec::Zero();
    double wsum = 0, wr2 = 0;
  };
  // Point i's row of the Jacobian at the current model, closest parameters and normals.
  auto jacobian_row = [&](std::size_t i) {
    Vec row;
    const double nv = normal[i].dot(model.v), nw = normal[i].dot(model.w);
    double pw = 1.0;
    for (int k = 0; k < kCoefficients; ++k, pw *= tau[i]) {
      row[k] = -nv * pw;
      row[kCoefficients + k] = -nw * pw;
    }
    row[kParams - 1] = -1.0;
    return row;
  };
  auto normal_equations = [&](double scale_mm) {
    Normal ne;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec row = jacobian_row(i);
      const double w = cauchy_weight(res[i], scale_mm);
      ne.H.noalias() += w * row * row.transpose();
      ne.g.noalias() += w * res[i] * row;
      ne.wsum += w;
      ne.wr2 += w * res[i] * res[i];
    }
    return ne;
  };

  residuals(model, res, tau, normal);
  double lambda = 1e-3;
  bool converged = false;
  for (int it = 0; it < params.max_iterations && !converged; ++it) {
    const double c = params.kernel_factor * sigma_of(res);
    const Normal ne = normal_equations(c);
    const double cost = cost_of(res, c);
    bool accepted = false;
    for (int tries = 0; tries < 12; ++tries) {
      Mat A = ne.H;
      for (int j = 0; j < kParams; ++j) A(j, j) += lambda * std::max(ne.H(j, j), 1e-12) + 1e-15;
      const Vec step = A.ldlt().solve(-ne.g);
      if (!step.allFinite()) {
        lambda *= 10;
        continue;
      }
      const SmoothTubeModel trial = apply(model, step);
      if (!(trial.tube_radius_mm > 0)) {
        lambda *= 10;
        continue;
      }
      residuals(trial, trial_res, trial_tau, trial_normal);
      if (cost_of(trial_res, c) <= cost) {
        model = trial;
        res.swap(trial_res);
        tau.swap(trial_tau);
        normal.swap(trial_normal);
        lambda = std::max(lambda * 0.2, 1e-9);
        accepted = true;
        if (step.cwiseAbs().maxCoeff() < 1e-7 * std::max(1.0, model.tube_radius_mm)) converged = true;
        break;
      }
      lambda *= 10;
    }
    if (!accepted) converged = true;  // no descent left: at the minimum
  }
  const double sigma = sigma_of(res);
  const Normal ne = normal_equations(params.kernel_factor * sigma);
  out.model = model;
  out.sigma_mm = sigma;
  out.rms_mm = ne.wsum > 0 ? std::sqrt(ne.wr2 / ne.wsum) : 0.0;

  // The curvature's peak over the window's middle: a grid, then a parabola through the best grid step.
  const double span = std::clamp(params.peak_fraction, 0.05, 1.0);
  constexpr int kGrid = 200;
  int best = 0;
  double best_k = -1.0;
  std::vector<double> kappa(kGrid + 1);
  for (int i = 0; i <= kGrid; ++i) {
    kappa[std::size_t(i)] = model.curvature(-span + 2.0 * span * i / kGrid);
    if (kappa[std::size_t(i)] > best_k) best_k = kappa[std::size_t(i)], best = i;
  }
  double peak = -span + 2.0 * span * best / kGrid;
  if (best > 0 && best < kGrid) {
    const double k0 = kappa[std::size_t(best - 1)], k1 = kappa[std::size_t(best)], k2 = kappa[std::size_t(best + 1)];
    const double den = k0 - 2.0 * k1 + k2;
    if (den < 0) peak += std::clamp(0.5 * (k0 - k2) / den, -0.5, 0.5) * (2.0 * span / kGrid);
  }
  const double peak_k = model.curvature(peak);
  out.peak_tau = peak;
  out.peak_point = model.point(peak);
  out.bend_radius_mm = peak_k > 0 ? 1.0 / peak_k : std::numeric_limits<double>::infinity();
  // Standard error by the delta method: the radius's gradient in the coefficients at the peak (the peak's own
  // shift is second order there), through the covariance of the weighted normal equations.
  const Eigen::LDLT<Mat> ldlt(ne.H);
  const Mat cov = ldlt.solve(Mat::Identity()) * (out.rms_mm * out.rms_mm);
  Vec grad = Vec::Zero();
  for (int j = 0; j < kParams - 1; ++j) {
    const double h = 1e-6 * std::max(1.0, model.tube_radius_mm);
    Vec x = Vec::Zero();
    x[j] = h;
    const double k = apply(model, x).curvature(peak);
    grad[j] = ((k > 0 ? 1.0 / k : 0.0) - out.bend_radius_mm) / h;
  }
  // Noise that neighbouring points share (SmoothTubeFitParams::noise): each point's influence on the radius,
  // w_i row_i . H^-1 grad, and the variance of their sum under the scan's correlation over independent noise's.
  if (params.noise) {
    const Vec b = ldlt.solve(grad);
    const double c = params.kernel_factor * sigma;
    std::vector<double> influence(n);
    for (std::size_t i = 0; i < n; ++i) influence[i] = cauchy_weight(res[i], c) * jacobian_row(i).dot(b);
    out.noise_inflation = b.allFinite() ? correlated_inflation(pts, influence, *params.noise)
                                        : std::max(1.0, params.noise->inflation);
  }
  const double var = grad.dot(cov * grad) * out.noise_inflation;
  out.bend_radius_se_mm = std::isfinite(var) && var >= 0 ? std::sqrt(var) : std::numeric_limits<double>::infinity();
  out.ok = converged && std::isfinite(out.bend_radius_mm) && model.tube_radius_mm > 0 &&
           std::isfinite(out.bend_radius_se_mm);
  return out;
}

}  // namespace ewis
