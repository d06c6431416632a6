// Beyond the paper (issue 7, 4c): a candidate inside the assembly or touching it is not a place a robot can
// put the sensor, however good the render looks.
#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "ewis/plan/score.hpp"

namespace ewis {
namespace {

// Closest point on triangle (a, b, c) to p (Ericson, Real-Time Collision Detection 5.1.5); returns distance^2.
double triangle_distance_sq(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.squaredNorm();
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.squaredNorm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + ab * (d1 / (d1 - d3)))).squaredNorm();
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.squaredNorm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + ac * (d2 / (d2 - d6)))).squaredNorm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))))).squaredNorm();
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) return std::min({ap.squaredNorm(), bp.squaredNorm(), cp.squaredNorm()});
  const double v = vb / denom, w = vc / denom;
  return (p - (a + ab * v + ac * w)).squaredNorm();
}

double box_distance_sq(const Eigen::Vector3d& p, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Vector3d d = (lo - p).cwiseMax(p - hi).cwiseMax(0.0);
  return d.squaredNorm();
}

bool geometry_within(const Scene& scene, const Eigen::Vector3d& p, double dist) {
  const double d2 = dist * dist;
  for (const Element& e : scene.elements) {
    if (box_distance_sq(p, e.bounds_min, e.bounds_max) > d2) continue;
    const std::uint32_t end = e.first_triangle + e.triangle_count;
    for (std::uint32_t t = e.first_triangle; t < end && t < scene.triangles.size(); ++t) {
      const Eigen::Vector3i& tri = scene.triangles[t];
      const Eigen::Vector3d a = scene.vertices[tri[0]].cast<double>();
      const Eigen::Vector3d b = scene.vertices[tri[1]].cast<double>();
      const Eigen::Vector3d c = scene.vertices[tri[2]].cast<double>();
      const Eigen::Vector3d lo = a.cwiseMin(b).cwiseMin(c), hi = a.cwiseMax(b).cwiseMax(c);
      if (box_distance_sq(p, lo, hi) > d2) continue;
      if (triangle_distance_sq(p, a, b, c) < d2) return true;
    }
  }
  return false;
}

// Majority vote of six axis rays: a ray whose first hit is the inner side of an outward-wound triangle
// starts inside a closed element. Six rays tolerate a stray open mesh or a ray along an edge.
bool inside_geometry(const Scene& scene, const Raycaster& caster, const Eigen::Vector3d& p) {
  static const std::array<Eigen::Vector3f, 6> dirs = {Eigen::Vector3f(1, 0, 0),  Eigen::Vector3f(-1, 0, 0),
                                                      Eigen::Vector3f(0, 1, 0),  Eigen::Vector3f(0, -1, 0),
                                                      Eigen::Vector3f(0, 0, 1),  Eigen::Vector3f(0, 0, -1)};
  int inner = 0;
  for (const auto& d : dirs) {
    Ray ray;
    ray.origin = p.cast<float>();
    ray.direction = d;
    const Hit hit = caster.cast(ray);
    if (!hit.hit() || hit.triangle >= scene.triangles.size()) continue;
    const Eigen::Vector3i& tri = scene.triangles[hit.triangle];
    const Eigen::Vector3f n = (scene.vertices[tri[1]] - scene.vertices[tri[0]])
                                  .cross(scene.vertices[tri[2]] - scene.vertices[tri[0]]);
    if (n.dot(d) > 0) ++inner;
  }
  return inner >= 4;
}

}  // namespace

std::string sensor_position_problem(const Scene& scene, const Raycaster& scene_caster,
                                    const Eigen::Vector3d& position, double min_distance_mm) {
  if (inside_geometry(scene, scene_caster, position)) return "inside geometry";
  if (min_distance_mm > 0 && geometry_within(scene, position, min_distance_mm)) {
    std::ostringstream s;
    s << "geometry within " << min_distance_mm << " mm";
    return s.str();
  }
  return "";
}

}  // namespace ewis
