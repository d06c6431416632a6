#include "ewis/sim/route.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace ewis::sim {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}

double RoutePiece::length_mm() const {
  if (kind == Kind::Straight) return (end - start).norm();
  return angle_rad * std::sqrt(a_mm * a_mm + b_mm * b_mm);
}

double RoutePiece::curvature_radius_mm() const {
  if (kind == Kind::Straight || a_mm <= 0.0) return kInf;
  return (a_mm * a_mm + b_mm * b_mm) / a_mm;
}

Eigen::Vector3d RoutePiece::at(double s) const {
  const double len = length_mm();
  s = std::clamp(s, 0.0, len);
  if (kind == Kind::Straight) return len > 0 ? Eigen::Vector3d(start + (end - start) * (s / len)) : start;
  const double t = s / std::sqrt(a_mm * a_mm + b_mm * b_mm);
  return center + a_mm * (std::cos(t) * u + std::sin(t) * v) + b_mm * t * w;
}

Eigen::Vector3d RoutePiece::tangent(double s) const {
  if (kind == Kind::Straight) {
    const Eigen::Vector3d d = end - start;
    return d.norm() > 0 ? Eigen::Vector3d(d.normalized()) : Eigen::Vector3d::UnitX();
  }
  const double l = std::sqrt(a_mm * a_mm + b_mm * b_mm);
  const double t = std::clamp(s, 0.0, length_mm()) / l;
  return (a_mm * (-std::sin(t) * u + std::cos(t) * v) + b_mm * w) / l;
}

double Route::length_mm() const {
  double total = 0;
  for (const auto& p : pieces) total += p.length_mm();
  return total;
}

double Route::min_curvature_radius_mm() const {
  double r = kInf;
  for (const auto& p : pieces) r = std::min(r, p.curvature_radius_mm());
  return r;
}

double Route::min_curvature_location_s() const {
  double r = kInf, s = 0, best = 0;
  for (const auto& p : pieces) {
    if (p.curvature_radius_mm() < r) {
      r = p.curvature_radius_mm();
      best = s + 0.5 * p.length_mm();
    }
    s += p.length_mm();
  }
  return best;
}

Eigen::Vector3d Route::at(double s) const {
  if (pieces.empty()) return Eigen::Vector3d::Zero();
  for (const auto& p : pieces) {
    const double len = p.length_mm();
    if (s <= len) return p.at(s);
    s -= len;
  }
  return pieces.back().at(pieces.back().length_mm());
}

Eigen::Vector3d Route::tangent(double s) const {
  if (pieces.empty()) return Eigen::Vector3d::UnitX();
  for (const auto& p : pieces) {
    const double len = p.length_mm();
    if (s <= len) return p.tangent(s);
    s -= len;
  }
  return pieces.back().tangent(pieces.back().length_mm());
}

std::optional<Route> fillet_route(const std::vector<Eigen::Vector3d>& corners, const std::vector<double>& radii,
                                  double min_straight_mm) {
  const std::size_t n = corners.size();
  if (n < 2 || radii.size() != n) return std::nullopt;
  for (std::size_t i = 0; i + 1 < n; ++i)
    if ((corners[i + 1] - corners[i]).norm() < 1e-6) return std::nullopt;
  // Per interior corner: arc start/end points and the helix (b = 0) describing the fillet.
  std::vector<Eigen::Vector3d> run_start(n - 1), run_end(n - 1);
  std::vector<std::optional<RoutePiece>> arcs(n);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    run_start[i] = corners[i];
    run_end[i] = corners[i + 1];
  }
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const Eigen::Vector3d d1 = (corners[i] - corners[i - 1]).normalized();
    const Eigen::Vector3d d2 = (corners[i + 1] - corners[i]).normalized();
    const double theta = std::acos(std::clamp(d1.dot(d2), -1.0, 1.0));
    if (theta < 1e-9) continue;                       // collinear: no bend
    if (theta > M_PI - 1e-3 || radii[i] <= 0) return std::nullopt;  // a U-turn back onto itself
    const double tangent_len = radii[i] * std::tan(theta / 2.0);
    const Eigen::Vector3d p1 = corners[i] - d1 * tangent_len;
    const Eigen::Vector3d p2 = corners[i] + d2 * tangent_len;
    const Eigen::Vector3d toward_center = (d2 - d1 * d1.dot(d2)).normalized();
    RoutePiece arc;
    arc.kind = RoutePiece::Kind::Helix;
    arc.center = p1 + radii[i] * toward_center;
    arc.u = -toward_center;
    arc.v = d1;
    arc.w = arc.u.cross(arc.v);
    arc.a_mm = radii[i];
    arc.b_mm = 0.0;
    arc.angle_rad = theta;
    arcs[i] = arc;
    run_end[i - 1] = p1;
    run_start[i] = p2;
  }
  Route route;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const Eigen::Vector3d dir = corners[i + 1] - corners[i];
    const double along = (run_end[i] - run_start[i]).dot(dir.normalized());
    if (along < min_straight_mm - 1e-9) return std::nullopt;  // fillets overlap on this run
    if (i > 0 && arcs[i]) route.pieces.push_back(*arcs[i]);
    if (along > 1e-9) {
      RoutePiece run;
      run.kind = RoutePiece::Kind::Straight;
      run.start = run_start[i];
      run.end = run_end[i];
      route.pieces.push_back(run);
    }
  }
  return route;
}

bool append_helix(Route& route, const Eigen::Vector3d& bend_toward, double a, double b, double angle_rad) {
  const Eigen::Vector3d p = route.end();
  const Eigen::Vector3d t = route.tangent(route.length_mm());
  Eigen::Vector3d d = bend_toward - t * t.dot(bend_toward);
  if (d.norm() < 1e-9 || a <= 0) return false;
  d.normalize();
  // The helix's principal normal at t=0 is -u (toward its axis) and its tangent (a v + b w)/L must equal t:
  // with m = t x u, v = (a t + b m)/L and w = (b t - a m)/L satisfy both and are orthonormal.
  const double l = std::sqrt(a * a + b * b);
  RoutePiece h;
  h.kind = RoutePiece::Kind::Helix;
  h.u = -d;
  const Eigen::Vector3d m = t.cross(h.u);
  h.v = (a * t + b * m) / l;
  h.w = (b * t - a * m) / l;
  h.a_mm = a;
  h.b_mm = b;
  h.angle_rad = angle_rad;
  h.center = p - a * h.u;
  route.pieces.push_back(h);
  return true;
}

void append_straight(Route& route, double length_mm) {
  RoutePiece run;
  run.kind = RoutePiece::Kind::Straight;
  run.start = route.end();
  run.end = run.start + route.tangent(route.length_mm()) * length_mm;
  route.pieces.push_back(run);
}

std::vector<Eigen::Vector3d> sample_route(const Route& route, double max_spacing_mm) {
  std::vector<Eigen::Vector3d> out;
  max_spacing_mm = std::max(max_spacing_mm, 1e-3);
  for (const auto& p : route.pieces) {
    const double len = p.length_mm();
    const int steps = std::max(1, static_cast<int>(std::ceil(len / max_spacing_mm - 1e-9)));
    for (int k = out.empty() ? 0 : 1; k <= steps; ++k) out.push_back(p.at(len * k / steps));
  }
  return out;
}

double polyline_length(const std::vector<Eigen::Vector3d>& points) {
  double total = 0;
  for (std::size_t i = 1; i < points.size(); ++i) total += (points[i] - points[i - 1]).norm();
  return total;
}

double polyline_min_curvature_radius(const std::vector<Eigen::Vector3d>& points, double window_mm,
                                     double straight_above_mm) {
  if (points.size() < 3) return kInf;
  const double spacing = polyline_length(points) / (points.size() - 1);
  const std::size_t k = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(window_mm / spacing)));
  double best = kInf;
  for (std::size_t i = k; i + k < points.size(); ++i) {
    const Eigen::Vector3d a = points[i - k] - points[i], b = points[i + k] - points[i];
    const Eigen::Vector3d c = points[i + k] - points[i - k];
    const double cross = a.cross(b).norm();
    if (cross < 1e-12) continue;
    const double r = a.norm() * b.norm() * c.norm() / (2.0 * cross);  // circumradius
    if (r < straight_above_mm) best = std::min(best, r);
  }
  return best;
}

}  // namespace ewis::sim
