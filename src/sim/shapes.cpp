#include "ewis/sim/shapes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <Eigen/Geometry>

namespace { using V3 = Eigen::Vector3d; }

namespace ewis::sim {

Shape make_box_shape(const Pose& frame, const Eigen::Vector3d& half_extents_mm) {
  Shape s;
  s.kind = Shape::Kind::Box;
  s.frame = frame;
  s.half_extents_mm = half_extents_mm;
  return s;
}

Shape make_aabb_shape(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  Pose f = Pose::Identity();
  f.translation() = 0.5 * (lo + hi);
  return make_box_shape(f, 0.5 * (hi - lo).cwiseAbs());
}

Shape make_sphere_shape(const Eigen::Vector3d& center, double radius_mm) {
  Shape s;
  s.kind = Shape::Kind::Sphere;
  s.frame.translation() = center;
  s.radius_mm = radius_mm;
  return s;
}

namespace {
// A frame whose z axis is `axis`.
Pose frame_with_z(const Eigen::Vector3d& origin, const Eigen::Vector3d& axis) {
  Pose f = Pose::Identity();
  f.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis.normalized()).toRotationMatrix();
  f.translation() = origin;
  return f;
}
}  // namespace

Shape make_cylinder_shape(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius_mm) {
  Shape s;
  s.kind = Shape::Kind::Cylinder;
  s.frame = frame_with_z(0.5 * (a + b), b - a);
  s.radius_mm = radius_mm;
  s.length_mm = (b - a).norm();
  return s;
}

Shape make_torus_shape(const Eigen::Vector3d& center, const Eigen::Vector3d& axis, double major_radius_mm,
                       double minor_radius_mm) {
  Shape s;
  s.kind = Shape::Kind::Torus;
  s.frame = frame_with_z(center, axis);
  s.major_radius_mm = major_radius_mm;
  s.radius_mm = minor_radius_mm;
  return s;
}

double distance_to_shape(const Shape& s, const Eigen::Vector3d& p) {
  const Eigen::Vector3d q = s.frame.linear().transpose() * (p - s.frame.translation());
  switch (s.kind) {
    case Shape::Kind::Box:
      return (q.cwiseAbs() - s.half_extents_mm).cwiseMax(0.0).norm();
    case Shape::Kind::Sphere:
      return std::max(q.norm() - s.radius_mm, 0.0);
    case Shape::Kind::Cylinder: {
      const double dx = std::max(std::hypot(q.x(), q.y()) - s.radius_mm, 0.0);
      const double dz = std::max(std::abs(q.z()) - 0.5 * s.length_mm, 0.0);
      return std::hypot(dx, dz);
    }
    case Shape::Kind::Torus: {
      const double rho = std::hypot(q.x(), q.y());
      return std::max(std::hypot(rho - s.major_radius_mm, q.z()) - s.radius_mm, 0.0);
    }
  }
  return 0.0;
}

Mesh shape_mesh(const Shape& s) {
  Mesh m;
  switch (s.kind) {
    case Shape::Kind::Box:
      m = make_box(-s.half_extents_mm, s.half_extents_mm);
      break;
    case Shape::Kind::Sphere:
      m = make_sphere(Eigen::Vector3d::Zero(), s.radius_mm, 72, 36);
      break;
    case Shape::Kind::Cylinder:
      m = make_cylinder(Eigen::Vector3d(0, 0, -0.5 * s.length_mm), Eigen::Vector3d(0, 0, 0.5 * s.length_mm),
                        s.radius_mm, 72);
      break;
    case Shape::Kind::Torus:
      m = make_torus(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), s.major_radius_mm, s.radius_mm, 96, 24);
      break;
  }
  transform_mesh(m, s.frame.linear(), s.frame.translation());
  return m;
}

void append_mesh(Mesh& a, const Mesh& b) {
  const int offset = static_cast<int>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const auto& t : b.triangles) a.triangles.push_back(t + Eigen::Vector3i::Constant(offset));
}

double Solid::distance(const Eigen::Vector3d& p) const {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& s : shapes) d = std::min(d, distance_to_shape(s, p));
  return d;
}

Mesh Solid::mesh() const {
  Mesh m;
  for (const auto& s : shapes) append_mesh(m, shape_mesh(s));
  return m;
}

namespace {

// Golden-section minimum of f on [lo, hi] (f unimodal there); 60 steps shrink the bracket by 1e-12.
template <class F>
double golden_min(const F& f, double lo, double hi, double& s_out) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double a = lo, b = hi;
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = f(c), fd = f(d);
  for (int it = 0; it < 60 && b - a > 1e-9; ++it) {
    if (fc < fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - g * (b - a);
      fc = f(c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + g * (b - a);
      fd = f(d);
    }
  }
  s_out = 0.5 * (a + b);
  return f(s_out);
}

std::vector<double> grid(double length, double step) {
  const int n = std::max(1, static_cast<int>(std::ceil(length / step)));
  std::vector<double> s(n + 1);
  for (int i = 0; i <= n; ++i) s[i] = length * i / n;
  return s;
}

}  // namespace

GapResult tube_solid_gap(const Tube& tube, const Solid& solid) {
  const Route& r = *tube.route;
  const double len = r.length_mm();
  const std::vector<double> s = grid(len, 0.5);
  std::vector<double> d(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) d[i] = solid.distance(r.at(s[i]));
  // Refine every local minimum within 2 mm of the coarse best (a union of shapes may have several).
  const double coarse_best = *std::min_element(d.begin(), d.end());
  GapResult best;
  best.gap_mm = std::numeric_limits<double>::infinity();
  const auto f = [&](double x) { return solid.distance(r.at(x)); };
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (d[i] > coarse_best + 2.0) continue;
    if ((i > 0 && d[i - 1] < d[i]) || (i + 1 < s.size() && d[i + 1] < d[i])) continue;
    double si = s[i];
    const double di = golden_min(f, s[std::max<std::size_t>(i, 1) - 1], s[std::min(i + 1, s.size() - 1)], si);
    if (di - tube.radius_mm < best.gap_mm) {
      best.gap_mm = di - tube.radius_mm;
      best.s_mm = si;
    }
  }
  // A minimum at an end of the route: the cable ends in a flat cap, not a hemisphere; measure to the cap
  // disk (its rim and rings inside it) instead of the ball around the end point.
  if (best.s_mm < 1e-6 || best.s_mm > len - 1e-6) {
    const bool at_start = best.s_mm < 1e-6;
    const V3 c = r.at(at_start ? 0.0 : len), t = r.tangent(at_start ? 0.0 : len);
    V3 e1 = t.unitOrthogonal(), e2 = t.cross(e1);
    double cap = solid.distance(c);
    for (int ring = 1; ring <= 8; ++ring)
      for (int k = 0; k < 180; ++k) {
        const double a = 2.0 * M_PI * k / 180.0, rr = tube.radius_mm * ring / 8.0;
        cap = std::min(cap, solid.distance(c + rr * (std::cos(a) * e1 + std::sin(a) * e2)));
      }
    // The rim and the disk are surface points, so this is the surface's distance (the ball model is a
    // lower bound that only differs here).
    best.gap_mm = std::max(best.gap_mm, cap);
  }
  best.on_cable = r.at(best.s_mm);
  best.on_other = best.on_cable;
  return best;
}

GapResult tube_tube_gap(const Tube& a, const Tube& b) {
  const Route& ra = *a.route;
  const Route& rb = *b.route;
  const std::vector<double> sa = grid(ra.length_mm(), 1.0), sb = grid(rb.length_mm(), 1.0);
  std::vector<Eigen::Vector3d> pa(sa.size()), pb(sb.size());
  for (std::size_t i = 0; i < sa.size(); ++i) pa[i] = ra.at(sa[i]);
  for (std::size_t j = 0; j < sb.size(); ++j) pb[j] = rb.at(sb[j]);
  double best = std::numeric_limits<double>::infinity();
  std::size_t bi = 0, bj = 0;
  for (std::size_t i = 0; i < pa.size(); ++i)
    for (std::size_t j = 0; j < pb.size(); ++j) {
      const double d2 = (pa[i] - pb[j]).squaredNorm();
      if (d2 < best) {
        best = d2;
        bi = i;
        bj = j;
      }
    }
  // Alternating golden-section refinement on the analytic routes around the coarse pair.
  double s1 = sa[bi], s2 = sb[bj];
  double d = std::sqrt(best);
  for (int round = 0; round < 30; ++round) {
    double n1 = s1, n2 = s2;
    golden_min([&](double x) { return (ra.at(x) - rb.at(s2)).norm(); }, std::max(0.0, s1 - 1.5),
               std::min(ra.length_mm(), s1 + 1.5), n1);
    const double dn = golden_min([&](double x) { return (ra.at(n1) - rb.at(x)).norm(); }, std::max(0.0, s2 - 1.5),
                                 std::min(rb.length_mm(), s2 + 1.5), n2);
    const bool moved = std::abs(n1 - s1) + std::abs(n2 - s2) > 1e-9;
    if (dn <= d) {
      d = dn;
      s1 = n1;
      s2 = n2;
    }
    if (!moved) break;
  }
  GapResult g;
  g.gap_mm = d - a.radius_mm - b.radius_mm;
  g.s_mm = s1;
  g.on_cable = ra.at(s1);
  g.on_other = rb.at(s2);
  return g;
}

}  // namespace ewis::sim
