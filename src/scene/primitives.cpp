// Closed, outward-oriented triangle meshes of analytic shapes.
#include "ewis/scene/primitives.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace ewis {
namespace {

int add_vertex(Mesh& m, const Eigen::Vector3d& p) {
  m.vertices.push_back(p.cast<float>());
  return static_cast<int>(m.vertices.size()) - 1;
}

// Quad a-b-c-d counter-clockwise seen from outside.
void add_quad(Mesh& m, int a, int b, int c, int d) {
  m.triangles.emplace_back(a, b, c);
  m.triangles.emplace_back(a, c, d);
}

// Any unit vector perpendicular to `n`.
Eigen::Vector3d perpendicular(const Eigen::Vector3d& n) {
  const Eigen::Vector3d helper = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return n.cross(helper).normalized();
}

// Appends a ring of `segments` vertices around `center` in the plane spanned by u, v (u x v = axis).
int add_ring(Mesh& m, const Eigen::Vector3d& center, const Eigen::Vector3d& u, const Eigen::Vector3d& v,
             double radius, int segments) {
  const int first = static_cast<int>(m.vertices.size());
  for (int s = 0; s < segments; ++s) {
    const double a = 2.0 * M_PI * s / segments;
    add_vertex(m, center + radius * (std::cos(a) * u + std::sin(a) * v));
  }
  return first;
}

// Side quads between ring r0 and ring r1 (r1 further along u x v): outward for rings made by add_ring.
void connect_rings(Mesh& m, int r0, int r1, int segments) {
  for (int s = 0; s < segments; ++s) {
    const int s1 = (s + 1) % segments;
    add_quad(m, r0 + s, r0 + s1, r1 + s1, r1 + s);
  }
}

// Fan cap: `facing_forward` when the cap's outside is along +axis (u x v).
void add_cap(Mesh& m, int ring, const Eigen::Vector3d& center, int segments, bool facing_forward) {
  const int c = add_vertex(m, center);
  for (int s = 0; s < segments; ++s) {
    const int s1 = (s + 1) % segments;
    if (facing_forward)
      m.triangles.emplace_back(c, ring + s, ring + s1);
    else
      m.triangles.emplace_back(c, ring + s1, ring + s);
  }
}

}  // namespace

Mesh make_box(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& max_corner) {
  Mesh m;
  const Eigen::Vector3d lo = min_corner.cwiseMin(max_corner), hi = min_corner.cwiseMax(max_corner);
  // Vertex i has x from bit 0, y from bit 1, z from bit 2.
  for (int i = 0; i < 8; ++i)
    add_vertex(m, Eigen::Vector3d(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z()));
  add_quad(m, 0, 2, 3, 1);  // z = lo, outward -z
  add_quad(m, 4, 5, 7, 6);  // z = hi, +z
  add_quad(m, 0, 1, 5, 4);  // y = lo, -y
  add_quad(m, 2, 6, 7, 3);  // y = hi, +y
  add_quad(m, 0, 4, 6, 2);  // x = lo, -x
  add_quad(m, 1, 3, 7, 5);  // x = hi, +x
  return m;
}

Mesh make_sphere(const Eigen::Vector3d& center, double radius_mm, int segments, int rings) {
  segments = std::max(segments, 3);
  rings = std::max(rings, 2);
  Mesh m;
  const int north = add_vertex(m, center + radius_mm * Eigen::Vector3d::UnitZ());
  int prev = -1;
  int first_ring = -1;
  for (int r = 1; r < rings; ++r) {
    const double theta = M_PI * r / rings;  // colatitude
    const int ring = add_ring(m, center + radius_mm * std::cos(theta) * Eigen::Vector3d::UnitZ(),
                              Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), radius_mm * std::sin(theta),
                              segments);
    if (prev >= 0) connect_rings(m, ring, prev, segments);  // going down: ring is "behind" prev along +z
    else first_ring = ring;
    prev = ring;
  }
  const int south = add_vertex(m, center - radius_mm * Eigen::Vector3d::UnitZ());
  for (int s = 0; s < segments; ++s) {
    const int s1 = (s + 1) % segments;
    m.triangles.emplace_back(north, first_ring + s, first_ring + s1);
    m.triangles.emplace_back(south, prev + s1, prev + s);
  }
  return m;
}

Mesh make_cylinder(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius_mm, int segments) {
  segments = std::max(segments, 3);
  Mesh m;
  const Eigen::Vector3d axis = (b - a).normalized();
  const Eigen::Vector3d u = perpendicular(axis), v = axis.cross(u);
  const int r0 = add_ring(m, a, u, v, radius_mm, segments);
  const int r1 = add_ring(m, b, u, v, radius_mm, segments);
  connect_rings(m, r0, r1, segments);
  add_cap(m, r0, a, segments, false);
  add_cap(m, r1, b, segments, true);
  return m;
}

Mesh make_torus(const Eigen::Vector3d& center, const Eigen::Vector3d& axis, double major_radius_mm,
                double minor_radius_mm, int major_segments, int minor_segments) {
  major_segments = std::max(major_segments, 3);
  minor_segments = std::max(minor_segments, 3);
  Mesh m;
  const Eigen::Vector3d n = axis.normalized();
  const Eigen::Vector3d e1 = perpendicular(n), e2 = n.cross(e1);
  for (int i = 0; i < major_segments; ++i) {
    const double phi = 2.0 * M_PI * i / major_segments;
    const Eigen::Vector3d radial = std::cos(phi) * e1 + std::sin(phi) * e2;
    for (int j = 0; j < minor_segments; ++j) {
      const double psi = 2.0 * M_PI * j / minor_segments;
      add_vertex(m, center + (major_radius_mm + minor_radius_mm * std::cos(psi)) * radial +
                        minor_radius_mm * std::sin(psi) * n);
    }
  }
  auto id = [&](int i, int j) { return (i % major_segments) * minor_segments + (j % minor_segments); };
  for (int i = 0; i < major_segments; ++i)
    for (int j = 0; j < minor_segments; ++j)
      // d/dphi x d/dpsi points outward of the tube for this parametrisation.
      add_quad(m, id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
  return m;
}

Mesh make_tube(const std::vector<Eigen::Vector3d>& centerline, double radius_mm, int segments) {
  segments = std::max(segments, 3);
  Mesh m;
  // Drop repeated points: they have no tangent.
  std::vector<Eigen::Vector3d> pts;
  for (const Eigen::Vector3d& p : centerline)
    if (pts.empty() || (p - pts.back()).norm() > 1e-9 * std::max(1.0, radius_mm)) pts.push_back(p);
  if (pts.size() < 2) return m;
  const std::size_t n = pts.size();
  // Tangent at each point: bisector of the adjacent segment directions.
  std::vector<Eigen::Vector3d> tangent(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d in = i > 0 ? Eigen::Vector3d((pts[i] - pts[i - 1]).normalized()) : Eigen::Vector3d::Zero();
    const Eigen::Vector3d out = i + 1 < n ? Eigen::Vector3d((pts[i + 1] - pts[i]).normalized()) : Eigen::Vector3d::Zero();
    Eigen::Vector3d t = in + out;
    tangent[i] = t.norm() > 1e-12 ? t.normalized() : (out.norm() > 0 ? out : in);
  }
  // Rotation-minimising frames by double reflection (Wang et al. 2008): no twist along the tube.
  Eigen::Vector3d r = perpendicular(tangent[0]);
  std::vector<int> rings(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0) {
      const Eigen::Vector3d v1 = pts[i] - pts[i - 1];
      const double c1 = v1.squaredNorm();
      const Eigen::Vector3d rl = r - (2.0 / c1) * v1.dot(r) * v1;
      const Eigen::Vector3d tl = tangent[i - 1] - (2.0 / c1) * v1.dot(tangent[i - 1]) * v1;
      const Eigen::Vector3d v2 = tangent[i] - tl;
      const double c2 = v2.squaredNorm();
      r = c2 > 1e-20 ? Eigen::Vector3d(rl - (2.0 / c2) * v2.dot(rl) * v2) : rl;
      r = (r - r.dot(tangent[i]) * tangent[i]).normalized();  // re-orthogonalise against drift
    }
    const Eigen::Vector3d s = tangent[i].cross(r);
    rings[i] = add_ring(m, pts[i], r, s, radius_mm, segments);
  }
  for (std::size_t i = 0; i + 1 < n; ++i) connect_rings(m, rings[i], rings[i + 1], segments);
  add_cap(m, rings.front(), pts.front(), segments, false);
  add_cap(m, rings.back(), pts.back(), segments, true);
  return m;
}

void transform_mesh(Mesh& mesh, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation) {
  for (Eigen::Vector3f& v : mesh.vertices) v = (rotation * v.cast<double>() + translation).cast<float>();
  // A mirror turns the mesh inside out: wound back, it stays outward (the simulator's brackets stood in frames of
  // either hand, and half of them were written inside out).
  if (rotation.determinant() < 0.0)
    for (Eigen::Vector3i& t : mesh.triangles) std::swap(t[1], t[2]);
}

}  // namespace ewis
