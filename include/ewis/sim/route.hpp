#pragma once
// Cable routes with analytically known length and curvature: a chain of straight runs and circular helices
// (a planar circular arc is a helix of zero pitch). Harness CAD routes a cable as a polyline of corners with
// a bend radius at each corner; fillet_route builds exactly that. For a helix of radius a and pitch 2*pi*b
// the curvature radius is (a^2 + b^2) / a everywhere on it, so every route's minimum bend radius is exact.
#include <Eigen/Core>
#include <limits>
#include <optional>
#include <vector>

namespace ewis::sim {

struct RoutePiece {
  enum class Kind { Straight, Helix };
  Kind kind = Kind::Straight;
  // Straight: from start to end.
  Eigen::Vector3d start = Eigen::Vector3d::Zero(), end = Eigen::Vector3d::Zero();
  // Helix: p(t) = center + a (cos t u + sin t v) + b t w, t in [0, angle_rad]; u, v, w orthonormal.
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d u = Eigen::Vector3d::UnitX(), v = Eigen::Vector3d::UnitY(), w = Eigen::Vector3d::UnitZ();
  double a_mm = 0.0, b_mm = 0.0, angle_rad = 0.0;

  double length_mm() const;
  // Radius of curvature: infinity for a straight run, (a^2 + b^2) / a for a helix.
  double curvature_radius_mm() const;
  Eigen::Vector3d at(double s_mm) const;       // s: arc length from the piece's start, clamped
  Eigen::Vector3d tangent(double s_mm) const;  // unit
};

struct Route {
  std::vector<RoutePiece> pieces;

  double length_mm() const;
  // Smallest curvature radius over the pieces; infinity when the route is straight.
  double min_curvature_radius_mm() const;
  // Arc length (from the route's start) of the middle of the piece with the smallest curvature radius.
  double min_curvature_location_s() const;
  Eigen::Vector3d at(double s_mm) const;  // clamped to [0, length]
  Eigen::Vector3d tangent(double s_mm) const;
  Eigen::Vector3d start() const { return at(0.0); }
  Eigen::Vector3d end() const { return at(length_mm()); }
};

// A route through `corners` with a circular fillet of radius radii[i] at every interior corner i
// (radii.size() == corners.size(), the first and last ignored). Empty when a fillet does not fit
// (tangent lengths overlap on a run), a run is shorter than min_straight_mm, or corners coincide.
std::optional<Route> fillet_route(const std::vector<Eigen::Vector3d>& corners, const std::vector<double>& radii,
                                  double min_straight_mm = 0.0);

// Appends a helix leaving the route's end tangentially: it bends toward `bend_toward` (made perpendicular to
// the end tangent), with radius a, rise parameter b (pitch 2*pi*b) and sweep angle. Returns false when
// `bend_toward` is parallel to the tangent.
bool append_helix(Route& route, const Eigen::Vector3d& bend_toward, double a_mm, double b_mm, double angle_rad);
// Appends a straight run along the route's end tangent.
void append_straight(Route& route, double length_mm);

// Dense centreline: every piece split into equal steps no longer than max_spacing_mm (end points exact).
std::vector<Eigen::Vector3d> sample_route(const Route& route, double max_spacing_mm);

// Numeric measures of a polyline (to check routes and, in tests, anything that outputs a centreline).
double polyline_length(const std::vector<Eigen::Vector3d>& points);
// Smallest radius of the circles through points i-k, i, i+k with k chosen so the chord is ~window_mm;
// infinity for a straight polyline (radius above straight_above_mm counts as straight).
double polyline_min_curvature_radius(const std::vector<Eigen::Vector3d>& points, double window_mm,
                                     double straight_above_mm = 1e5);

}  // namespace ewis::sim
