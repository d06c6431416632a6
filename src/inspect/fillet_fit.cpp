// Line-arc-line (fillet) fit to a bent tube's surface points (see fillet_fit.hpp).
#include "ewis/inspect/fillet_fit.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "ewis/core/cloud.hpp"
#include "ewis/core/robust.hpp"
#include "ewis/inspect/distance_gradient.hpp"

namespace ewis {
namespace {

constexpr double kMaxTiltRad = 1.2;  // beyond it the helix climbs steeper than it turns: no bend's shape
// Parameters: vertex (3), leg1 tangent (2), leg2 tangent (2), log bend radius, tube radius; and the tilt when it is
// free (a planar fit keeps the 9-parameter system, and with it the arithmetic it always had).
constexpr int kPlanarParams = 9, kTiltedParams = 10;
template <int N>
using Vec = Eigen::Matrix<double, N, 1>;
template <int N>
using Mat = Eigen::Matrix<double, N, N>;

// Two unit vectors perpendicular to u (a tangent basis for a direction's update).
void tangent_basis(const Eigen::Vector3d& u, Eigen::Vector3d& e1, Eigen::Vector3d& e2) {
  e1 = u.unitOrthogonal();
  e2 = u.cross(e1);
}

// The model moved by x (relative to `base`, in the local parameterisation).
template <int N>
FilletModel apply(const FilletModel& base, const Vec<N>& x) {
  FilletModel m = base;
  Eigen::Vector3d a1, a2, b1, b2;
  tangent_basis(base.leg1, a1, a2);
  tangent_basis(base.leg2, b1, b2);
  m.vertex = base.vertex + x.template head<3>();
  m.leg1 = (base.leg1 + x[3] * a1 + x[4] * a2).normalized();
  m.leg2 = (base.leg2 + x[5] * b1 + x[6] * b2).normalized();
  m.bend_radius_mm = base.bend_radius_mm * std::exp(std::clamp(x[7], -3.0, 3.0));
  m.tube_radius_mm = base.tube_radius_mm + x[8];
  if constexpr (N > kPlanarParams) m.tilt_rad = std::clamp(base.tilt_rad + x[9], -kMaxTiltRad, kMaxTiltRad);
  return m;
}

// The helix of a tilted model (see FilletModel::tilt_rad); false where it is degenerate (legs nearly parallel or
// opposite, a tilt that leaves no turn about the axis).
bool helix_of(const FilletModel& m, FilletHelix& h) {
  const double turn = m.turn_rad();
  const Eigen::Vector3d cross = m.leg1.cross(m.leg2), through = m.leg2 - m.leg1;
  if (!(turn > 1e-6) || cross.norm() < 1e-9 || through.norm() < 1e-9) return false;
  const Eigen::Vector3d t_in = -m.leg1, t_out = m.leg2;
  Eigen::Vector3d n = std::cos(m.tilt_rad) * cross.normalized() + std::sin(m.tilt_rad) * through.normalized();
  double s = t_in.dot(n);  // sine of the helix's climb: the same for both tangents
  if (std::abs(s) > 0.95) return false;
  const Eigen::Vector3d p_in = (t_in - s * n).normalized(), p_out = (t_out - s * n).normalized();
  double phi = std::atan2(p_in.cross(p_out).dot(n), p_in.dot(p_out));
  if (phi < 0) n = -n, s = -s, phi = -phi;
  if (!(phi > 1e-9)) return false;
  const double R = m.bend_radius_mm, c = std::sqrt(1.0 - s * s);
  h.n = n;
  h.rho = R * c * c;
  h.lift = R * s * c;
  h.phi_end = phi;
  h.e_t0 = p_in;
  h.e_n0 = n.cross(p_in);
  h.axis_point = Eigen::Vector3d::Zero();
  // Placed so that the middle of the legs' common perpendicular is the vertex.
  const Eigen::Vector3d x0 = h.at(0.0), x1 = h.at(phi), w0 = x0 - x1;
  const double b = t_in.dot(t_out), den = 1.0 - b * b;
  if (!(den > 1e-12)) return false;
  const double d = t_in.dot(w0), e = t_out.dot(w0);
  const double mu = (b * e - d) / den, nu = (e - b * d) / den;
  const Eigen::Vector3d middle = 0.5 * (x0 + mu * t_in + x1 + nu * t_out);
  h.axis_point = m.vertex - middle;
  h.start = x0 + h.axis_point;
  h.end = x1 + h.axis_point;
  return true;
}

// Distance from p to the half-line from `start` along the unit `dir` (a fillet's leg); `s`: the closest point's
// distance from the start.
double half_line_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& start, const Eigen::Vector3d& dir,
                          double& s) {
  s = std::max(0.0, (p - start).dot(dir));
  return (p - start - s * dir).norm();
}

// Distance from p to the helix over [0, phi_end] (infinity where its closest point lies beyond an end: the legs
// hold those points), by Newton steps on the squared distance from p's angle about the axis; `phi`: the closest
// point's angle.
double helix_distance(const FilletHelix& h, const Eigen::Vector3d& p, double& phi_out) {
  const Eigen::Vector3d w = p - h.axis_point;
  double phi = std::atan2(w.dot(h.e_t0), -w.dot(h.e_n0));
  const double mid = 0.5 * h.phi_end;
  while (phi < mid - M_PI) phi += 2.0 * M_PI;
  while (phi > mid + M_PI) phi -= 2.0 * M_PI;
  for (int it = 0; it < 8; ++it) {
    const Eigen::Vector3d u = -std::cos(phi) * h.e_n0 + std::sin(phi) * h.e_t0;
    const Eigen::Vector3d du = std::sin(phi) * h.e_n0 + std::cos(phi) * h.e_t0;
    const Eigen::Vector3d r = p - (h.axis_point + h.rho * u + h.lift * phi * h.n);
    const Eigen::Vector3d d1 = h.rho * du + h.lift * h.n, d2 = -h.rho * u;
    const double g = -r.dot(d1);
    double hh = d1.squaredNorm() - r.dot(d2);
    if (!(hh > 1e-12)) hh = d1.squaredNorm();
    const double step = std::clamp(-g / hh, -0.3, 0.3);
    phi += step;
    if (std::abs(step) < 1e-12) break;
  }
  phi_out = phi;
  if (phi < 0.0 || phi > h.phi_end) return std::numeric_limits<double>::infinity();
  return (p - h.at(phi)).norm();
}

// Each piece of a fillet's centreline as c = a + f1 b + f2 c + f3 d, with weights f that depend on the point along
// the piece only: the legs c = t + s leg; the arc c = centre + cos(phi) ea + sin(phi) (its spoke a quarter turn on
// towards eb); the helix c = axis_point - rho cos(phi) e_n0 + rho sin(phi) e_t0 + phi lift n. A model's small change
// moves a point of fixed weights by the change of these vectors.
enum Piece : std::uint8_t { kLeg1, kLeg2, kArc, kHelix, kPieces };
struct PieceFrames {
  Eigen::Vector3d a[kPieces], b[kPieces], c[kPieces], d[kPieces];
};

PieceFrames frames_of(const FilletShape& s) {
  PieceFrames f;
  for (int k = 0; k < kPieces; ++k) f.a[k] = f.b[k] = f.c[k] = f.d[k] = Eigen::Vector3d::Zero();
  f.a[kLeg1] = s.t1, f.b[kLeg1] = s.leg1;
  f.a[kLeg2] = s.t2, f.b[kLeg2] = s.leg2;
  if (s.has_arc) {
    f.a[kArc] = s.centre, f.b[kArc] = s.ea;
    f.c[kArc] = (s.s_ab >= 0 ? 1.0 : -1.0) * s.n.cross(s.ea);
  }
  if (s.helical) {
    const FilletHelix& h = s.helix;
    f.a[kHelix] = h.axis_point, f.b[kHelix] = -h.rho * h.e_n0, f.c[kHelix] = h.rho * h.e_t0, f.d[kHelix] = h.lift * h.n;
  }
  return f;
}

// The closest point of a fillet's centreline to a surface point: its piece, its weights on the piece's frame, and the
// unit vector from it to the point (the distance's gradient in the point's position; zero on the centreline).
struct FilletFoot {
  Piece piece = kLeg1;
  double f1 = 0, f2 = 0, f3 = 0;
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
};

// fillet_shape_distance, and with `foot` the closest point's description (the same distance, the same arithmetic).
double shape_distance(const FilletShape& s, const Eigen::Vector3d& p, FilletFoot* foot) {
  double s1 = 0, s2 = 0, phi = 0;
  const double d1 = half_line_distance(p, s.t1, s.leg1, s1), d2 = half_line_distance(p, s.t2, s.leg2, s2);
  double best = std::min(d1, d2);
  Piece piece = d2 < d1 ? kLeg2 : kLeg1;
  Eigen::Vector3d wp = Eigen::Vector3d::Zero();
  if (s.helical) {
    const double dh = helix_distance(s.helix, p, phi);
    if (dh < best) best = dh, piece = kHelix;
  } else if (s.has_arc) {
    const Eigen::Vector3d w = p - s.centre;
    const double h = w.dot(s.n);
    wp = w - h * s.n;
    // inside the arc's angle: wp lies between ea and eb (the short way; the turn is below pi)
    const bool inside = s.ea.cross(wp).dot(s.n) * s.s_ab >= 0 && wp.cross(s.eb).dot(s.n) * s.s_ab >= 0;
    if (inside) {
      const double da = std::hypot(wp.norm() - s.bend_radius_mm, h);
      if (da < best) best = da, piece = kArc;
    }
  }
  if (!foot) return best;
  FilletFoot& f = *foot;
  f = FilletFoot{};
  f.piece = piece;
  Eigen::Vector3d c;
  if (piece == kLeg1) {
    f.f1 = s1;
    c = s.t1 + s1 * s.leg1;
  } else if (piece == kLeg2) {
    f.f1 = s2;
    c = s.t2 + s2 * s.leg2;
  } else if (piece == kHelix) {
    f.f1 = std::cos(phi), f.f2 = std::sin(phi), f.f3 = phi;
    c = s.helix.at(phi);
  } else {
    const double r = wp.norm();
    const Eigen::Vector3d spoke = r > 0 ? Eigen::Vector3d(wp * (s.bend_radius_mm / r)) : Eigen::Vector3d(s.ea);
    const Eigen::Vector3d quarter = (s.s_ab >= 0 ? 1.0 : -1.0) * s.n.cross(s.ea);
    f.f1 = spoke.dot(s.ea) / s.ea.squaredNorm();
    f.f2 = spoke.dot(quarter) / quarter.squaredNorm();
    c = s.centre + spoke;
  }
  const Eigen::Vector3d to_point = p - c;
  const double len = to_point.norm();
  if (len > 0) f.u = to_point / len;
  return best;
}

// The derivative of the distance from a point to the centreline in a model parameter, from the change `delta` of the
// frames (per unit of the parameter): the closest point held at its weights (the envelope theorem: the closest point's
// own shift along the curve changes the distance only to second order).
double distance_derivative(const FilletFoot& f, const PieceFrames& delta) {
  const int k = f.piece;
  return -f.u.dot(delta.a[k] + f.f1 * delta.b[k] + f.f2 * delta.c[k] + f.f3 * delta.d[k]);
}

}  // namespace

double fillet_robust_cost(const std::vector<Eigen::Vector3d>& points, const FilletModel& model, double scale_mm,
                          const std::vector<double>* noise_scale) {
  if (noise_scale && noise_scale->size() != points.size()) noise_scale = nullptr;
  const FilletShape shape = fillet_shape(model);
  double s = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double r = fillet_shape_distance(shape, points[i]) - model.tube_radius_mm;
    s += cauchy_rho(noise_scale ? r / std::max((*noise_scale)[i], 1e-6) : r, scale_mm);
  }
  return s;
}

std::vector<double> ray_noise_scales(const std::vector<Eigen::Vector3d>& points, const FilletModel& model,
                                     const Eigen::Vector3d& sensor) {
  const std::size_t n = points.size();
  std::vector<double> scale(n, 1.0);
  if (n < 40) return scale;
  // Each point's residual and cos^2 of its incidence (the outward normal: the distance's gradient).
  std::vector<double> res(n), c2(n);
  const FilletShape shape = fillet_shape(model);
  const auto dist = [&](const Eigen::Vector3d& y) { return fillet_shape_distance(shape, y); };
  for (std::size_t i = 0; i < n; ++i) {
    const double c = facing_cosine(dist, points[i], sensor);
    c2[i] = c * c;
    res[i] = dist(points[i]) - model.tube_radius_mm;
  }
  // Robust variance in four bins of cos^2 (by rank), then variance = a + b cos^2 by least squares, a, b >= 0.
  std::vector<std::uint32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = std::uint32_t(i);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) { return c2[x] < c2[y]; });
  constexpr int kBins = 4;
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  std::vector<double> bin, tmp;
  for (int k = 0; k < kBins; ++k) {
    const std::size_t lo = n * k / kBins, hi = n * (k + 1) / kBins;
    bin.clear();
    double mean_c2 = 0;
    for (std::size_t j = lo; j < hi; ++j) {
      bin.push_back(res[order[j]]);
      mean_c2 += c2[order[j]];
    }
    mean_c2 /= double(hi - lo);
    const double sd = robust_sigma(bin, 1e-6, tmp);
    sx += mean_c2, sy += sd * sd, sxx += mean_c2 * mean_c2, sxy += mean_c2 * sd * sd;
  }
  const double den = kBins * sxx - sx * sx;
  double b = den > 1e-12 ? (kBins * sxy - sx * sy) / den : 0.0;
  double a = (sy - b * sx) / kBins;
  if (b < 0) b = 0, a = sy / kBins;
  if (a < 0) a = 0, b = sxx > 0 ? sxy / sxx : 0.0;
  const double face_on = a + b;
  if (!(face_on > 0) || !(b > 0)) return scale;
  for (std::size_t i = 0; i < n; ++i) scale[i] = std::sqrt(std::max(a + b * c2[i], 0.25 * face_on));
  tmp = scale;
  const double mid = median_in_place(tmp);
  if (mid > 0)
    for (double& s : scale) s /= mid;
  return scale;
}

double FilletModel::turn_rad() const {
  return M_PI - std::acos(std::clamp(leg1.dot(leg2), -1.0, 1.0));
}

Eigen::Vector3d FilletHelix::at(double phi) const {
  return axis_point + rho * (-std::cos(phi) * e_n0 + std::sin(phi) * e_t0) + lift * phi * n;
}

FilletShape fillet_shape(const FilletModel& m) {
  FilletShape s;
  s.leg1 = m.leg1;
  s.leg2 = m.leg2;
  if (m.tilt_rad != 0.0 && helix_of(m, s.helix)) {
    s.helical = true;
    s.t1 = s.helix.start;
    s.t2 = s.helix.end;
    return s;
  }
  const double turn = m.turn_rad();
  const double R = m.bend_radius_mm;
  const double half = 0.5 * turn;
  const double tangent_len = R * std::tan(half);
  s.t1 = m.vertex + tangent_len * m.leg1;
  s.t2 = m.vertex + tangent_len * m.leg2;
  const Eigen::Vector3d bis = m.leg1 + m.leg2;
  const Eigen::Vector3d normal = m.leg1.cross(m.leg2);
  if (turn < 1e-9 || bis.norm() < 1e-12 || normal.norm() < 1e-12) return s;
  s.has_arc = true;
  s.bend_radius_mm = R;
  s.n = normal.normalized();
  s.centre = m.vertex + bis.normalized() * (R / std::cos(half));
  s.ea = s.t1 - s.centre;
  s.eb = s.t2 - s.centre;
  s.s_ab = s.ea.cross(s.eb).dot(s.n);
  return s;
}

double fillet_shape_distance(const FilletShape& s, const Eigen::Vector3d& p) { return shape_distance(s, p, nullptr); }

double fillet_centreline_distance(const FilletModel& m, const Eigen::Vector3d& p) {
  return fillet_shape_distance(fillet_shape(m), p);
}

namespace {

template <int kParams>
FilletFit fit_fillet_n(const std::vector<Eigen::Vector3d>& surface_points, const FilletModel& initial,
                       const FilletFitParams& params, const std::vector<double>* noise_scale) {
  using Vec = ewis::Vec<kParams>;
  using Mat = ewis::Mat<kParams>;
  FilletFit out;
  const std::vector<std::uint32_t> picked = evenly_strided(surface_points.size(), params.max_points);
  const std::vector<Eigen::Vector3d> pts = pick(surface_points, picked);
  std::vector<double> inv_scale(pts.size(), 1.0);
  if (noise_scale && noise_scale->size() == surface_points.size())
    for (std::size_t i = 0; i < pts.size(); ++i) inv_scale[i] = 1.0 / std::max((*noise_scale)[picked[i]], 1e-6);
  const std::size_t n = pts.size();
  out.points = n;
  if (n < 3 * kParams || !(initial.bend_radius_mm > 0) || !(initial.tube_radius_mm > 0)) return out;

  FilletModel model = initial;
  model.leg1.normalize();
  model.leg2.normalize();
  std::vector<double> res(n), tmp;
  // Residuals, and with `feet` each point's closest point on the centreline (for the Jacobian).
  std::vector<FilletFoot> feet(n), trial_feet(n);
  auto residuals = [&](const FilletModel& m, std::vector<double>& r, std::vector<FilletFoot>* ft) {
    const FilletShape shape = fillet_shape(m);
    for (std::size_t i = 0; i < n; ++i)
      r[i] = (shape_distance(shape, pts[i], ft ? &(*ft)[i] : nullptr) - m.tube_radius_mm) * inv_scale[i];
  };
  auto sigma_of = [&](const std::vector<double>& r) { return robust_sigma(r, params.min_noise_mm, tmp); };
  auto cost_of = [&](const std::vector<double>& r, double c) {
    double s = 0;
    for (double v : r) s += cauchy_rho(v, c);
    return s;
  };

  // The Jacobian in the local parameterisation at the current residuals (`feet` are theirs). The centreline's
  // frames are differenced forward (steps sized to each parameter's scale), and each point's derivative is its
  // closest point's shift along the unit vector to it: one evaluation per point and parameter of a sum of four
  // vectors instead of a distance (the derivative of the forward difference of the distances to first order; the
  // tube radius's column is -1). A step that changes the centreline's kind (the tilt leaving 0 makes the arc a
  // helix) has no common frame: its column is the forward difference of the residuals. Held parameters' columns
  // stay zero.
  Eigen::MatrixXd J(n, kParams);
  std::vector<double> shifted(n);
  const auto held = [&](int j) { return (j == 8 && !params.fit_tube_radius) || (j == 7 && !params.fit_bend_radius); };
  const auto step_scale = [](const FilletModel& m) { return std::max(m.tube_radius_mm, 0.5); };
  const auto jacobian = [&](const FilletModel& m) {
    const double scale = step_scale(m);
    const double h[kTiltedParams] = {1e-4 * scale, 1e-4 * scale, 1e-4 * scale, 1e-5, 1e-5, 1e-5, 1e-5, 1e-5,
                                     1e-5 * scale, 1e-5};
    const FilletShape shape = fillet_shape(m);
    const PieceFrames frames = frames_of(shape);
    for (int j = 0; j < kParams; ++j) {
      if (held(j)) {
        J.col(j).setZero();
        continue;
      }
      if (j == 8) {
        for (std::size_t i = 0; i < n; ++i) J(i, j) = -inv_scale[i];
        continue;
      }
      Vec x = Vec::Zero();
      x[j] = h[j];
      const FilletModel moved = apply<kParams>(m, x);
      const FilletShape moved_shape = fillet_shape(moved);
      if (moved_shape.helical != shape.helical || moved_shape.has_arc != shape.has_arc) {
        residuals(moved, shifted, nullptr);
        for (std::size_t i = 0; i < n; ++i) J(i, j) = (shifted[i] - res[i]) / h[j];
        continue;
      }
      PieceFrames delta = frames_of(moved_shape);
      for (int k = 0; k < kPieces; ++k) {
        delta.a[k] = (delta.a[k] - frames.a[k]) / h[j];
        delta.b[k] = (delta.b[k] - frames.b[k]) / h[j];
        delta.c[k] = (delta.c[k] - frames.c[k]) / h[j];
        delta.d[k] = (delta.d[k] - frames.d[k]) / h[j];
      }
      for (std::size_t i = 0; i < n; ++i) J(i, j) = distance_derivative(feet[i], delta) * inv_scale[i];
    }
  };
  // The Cauchy-weighted normal equations at the current residuals (and the weighted residual sums).
  struct Normal {
    Mat H = Mat::Zero();
    Vec g = Vec::Zero();
    double wsum = 0, wr2 = 0;
  };
  const auto normal_equations = [&](double scale_mm) {
    Normal ne;
    for (std::size_t i = 0; i < n; ++i) {
      const double w = cauchy_weight(res[i], scale_mm);
      const Eigen::Matrix<double, 1, kParams> row = J.row(i);
      ne.H.noalias() += w * row.transpose() * row;
      ne.g.noalias() += w * res[i] * row.transpose();
      ne.wsum += w;
      ne.wr2 += w * res[i] * res[i];
    }
    return ne;
  };

  residuals(model, res, &feet);
  double lambda = 1e-3;
  bool converged = false;
  for (int it = 0; it < params.max_iterations; ++it) {
    ++out.iterations;
    const double c = params.kernel_factor * sigma_of(res);
    jacobian(model);
    const Normal ne = normal_equations(c);
    const Mat& H = ne.H;
    const Vec& g = ne.g;
    const double scale = step_scale(model);
    const double cost = cost_of(res, c);
    bool accepted = false;
    for (int tries = 0; tries < 12; ++tries) {
      Mat A = H;
      for (int j = 0; j < kParams; ++j) A(j, j) += lambda * std::max(H(j, j), 1e-12) + 1e-15;
      const Vec step = A.ldlt().solve(-g);
      if (!step.allFinite()) {
        lambda *= 10;
        continue;
      }
      const FilletModel trial = apply<kParams>(model, step);
      if (!(trial.tube_radius_mm > 0) || trial.turn_rad() <= 1e-6) {
        lambda *= 10;
        continue;
      }
      residuals(trial, shifted, &trial_feet);
      if (cost_of(shifted, c) <= cost) {
        model = trial;
        res.swap(shifted);
        feet.swap(trial_feet);
        lambda = std::max(lambda * 0.2, 1e-9);
        accepted = true;
        const bool tilt_settled = kParams == kPlanarParams || std::abs(step[kParams - 1]) < 1e-7;
        if (step.template head<3>().norm() < 1e-5 * scale && step.template segment<4>(3).norm() < 1e-7 &&
            std::abs(step[7]) < 1e-7 && tilt_settled) {
          converged = true;
        }
        break;
      }
      lambda *= 10;
    }
    if (!accepted) {  // no descent left: at the minimum
      converged = true;
    }
    if (converged) break;
  }
  // Covariance of the bend radius from the weighted normal equations at the solution.
  const double sigma = sigma_of(res);
  jacobian(model);
  const Normal ne = normal_equations(params.kernel_factor * sigma);
  Mat H = ne.H;
  for (int j = 0; j < kParams; ++j)
    if (held(j)) H(j, j) = 1.0;  // a held parameter has no variance
  out.model = model;
  out.sigma_mm = sigma;
  out.rms_mm = ne.wsum > 0 ? std::sqrt(ne.wr2 / ne.wsum) : 0.0;
  // The bend radius's variance from the pseudo-inverse: where the window holds only the arc, its ends (two
  // combinations of the vertex and the legs) do not move the residuals, and those flat directions, whose inverse is
  // unbounded, are left out when the radius is not among them (else the radius is unknown: infinite variance).
  const Eigen::SelfAdjointEigenSolver<Mat> eigen(H);
  const double top = eigen.eigenvalues()[kParams - 1];
  double var = 0;
  Vec row7 = Vec::Zero();  // the pseudo-inverse's row of the log radius
  for (int k = 0; k < kParams; ++k) {
    const double ev = eigen.eigenvalues()[k], along = eigen.eigenvectors()(7, k);
    if (ev > 1e-10 * top) {
      var += along * along / ev;
      row7 += eigen.eigenvectors().col(k) * (along / ev);
    } else if (std::abs(along) > 1e-3) {
      var = std::numeric_limits<double>::infinity();
    }
  }
  // Noise that neighbouring points share (FilletFitParams::noise): each point's influence on the log radius,
  // w_i J_i . row7, and the variance of their sum under the scan's correlation over what independent noise gives.
  // A radius the data do not fix (a kink collapsing) takes the inflation of a mean, the largest for noise smoothed
  // over neighbours: its likelihood ratios must not count the correlated points as independent.
  if (params.noise && params.fit_bend_radius) {
    out.noise_inflation = std::max(1.0, params.noise->inflation);
    if (std::isfinite(var) && var > 0) {
      const double c = params.kernel_factor * sigma;
      std::vector<double> influence(n);
      for (std::size_t i = 0; i < n; ++i) influence[i] = cauchy_weight(res[i], c) * J.row(i).dot(row7);
      out.noise_inflation = correlated_inflation(pts, influence, *params.noise);
    }
  }
  // log-radius parameter: se(R) = R se(log R)
  var *= out.rms_mm * out.rms_mm * out.noise_inflation;
  out.bend_radius_se_mm = std::isfinite(var) && var >= 0 && top > 0 ? model.bend_radius_mm * std::sqrt(var)
                                                                    : std::numeric_limits<double>::infinity();
  out.ok = converged && std::isfinite(model.bend_radius_mm) && model.turn_rad() > 1e-3 && model.tube_radius_mm > 0;
  return out;
}

}  // namespace

FilletFit fit_fillet(const std::vector<Eigen::Vector3d>& surface_points, const FilletModel& initial,
                     const FilletFitParams& params, const std::vector<double>* noise_scale) {
  return params.fit_tilt ? fit_fillet_n<kTiltedParams>(surface_points, initial, params, noise_scale)
                         : fit_fillet_n<kPlanarParams>(surface_points, initial, params, noise_scale);
}

}  // namespace ewis
