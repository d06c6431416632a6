// Primitives against analytic area and enclosed volume; closedness and outward orientation.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <utility>

#include "ewis/scene/primitives.hpp"

namespace {

using ewis::Mesh;
using Eigen::Vector3d;

double area(const Mesh& m) {
  double a = 0;
  for (const auto& t : m.triangles) {
    const Vector3d p = m.vertices[t[0]].cast<double>(), q = m.vertices[t[1]].cast<double>(),
                   r = m.vertices[t[2]].cast<double>();
    a += 0.5 * (q - p).cross(r - p).norm();
  }
  return a;
}

// Divergence theorem: positive for a closed mesh with outward normals.
double volume(const Mesh& m) {
  double v = 0;
  for (const auto& t : m.triangles) {
    const Vector3d p = m.vertices[t[0]].cast<double>(), q = m.vertices[t[1]].cast<double>(),
                   r = m.vertices[t[2]].cast<double>();
    v += p.dot(q.cross(r)) / 6.0;
  }
  return v;
}

// Every directed edge appears once and its reverse once: closed, consistently oriented 2-manifold.
void expect_closed(const Mesh& m) {
  std::map<std::pair<int, int>, int> edges;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) edges[{t[k], t[(k + 1) % 3]}]++;
  for (const auto& [e, count] : edges) {
    ASSERT_EQ(count, 1) << "edge " << e.first << "-" << e.second << " used twice in one direction";
    ASSERT_EQ(edges.count({e.second, e.first}), 1u) << "open edge " << e.first << "-" << e.second;
  }
}

TEST(Primitives, BoxIsExact) {
  const Mesh m = ewis::make_box(Vector3d(-1, 2, 3), Vector3d(4, 5, 9));
  EXPECT_EQ(m.triangles.size(), 12u);
  expect_closed(m);
  EXPECT_NEAR(area(m), 2 * (5 * 3 + 5 * 6 + 3 * 6), 1e-4);
  EXPECT_NEAR(volume(m), 5 * 3 * 6, 1e-4);
}

TEST(Primitives, SphereConvergesToAnalytic) {
  const double r = 20;
  const Mesh m = ewis::make_sphere(Vector3d(5, -3, 7), r, 192, 96);
  expect_closed(m);
  const double a = 4 * M_PI * r * r, v = 4.0 / 3.0 * M_PI * r * r * r;
  // Inscribed polyhedron: slightly smaller; the error is O(angle^2) ~ (pi/96)^2.
  EXPECT_LT(area(m), a);
  EXPECT_NEAR(area(m), a, 1e-3 * a);
  EXPECT_LT(volume(m), v);
  EXPECT_NEAR(volume(m), v, 2e-3 * v);
  for (const auto& p : m.vertices) EXPECT_NEAR((p.cast<double>() - Vector3d(5, -3, 7)).norm(), r, 1e-4);
}

TEST(Primitives, CylinderConvergesToAnalytic) {
  const double r = 5, len = 80;
  const Vector3d a(1, 2, 3), dir = Vector3d(1, -2, 0.5).normalized();
  const Mesh m = ewis::make_cylinder(a, a + len * dir, r, 256);
  expect_closed(m);
  const double area_true = 2 * M_PI * r * len + 2 * M_PI * r * r, vol_true = M_PI * r * r * len;
  EXPECT_NEAR(area(m), area_true, 1e-3 * area_true);
  EXPECT_NEAR(volume(m), vol_true, 1e-3 * vol_true);
}

TEST(Primitives, TorusConvergesToAnalytic) {
  const double big = 60, small = 8;
  const Mesh m = ewis::make_torus(Vector3d(0, 10, -5), Vector3d(0.3, 1, 0.2), big, small, 384, 96);
  expect_closed(m);
  const double area_true = 4 * M_PI * M_PI * big * small, vol_true = 2 * M_PI * M_PI * big * small * small;
  EXPECT_NEAR(area(m), area_true, 2e-3 * area_true);
  EXPECT_NEAR(volume(m), vol_true, 2e-3 * vol_true);
}

TEST(Primitives, StraightTubeEqualsCylinder) {
  std::vector<Vector3d> line;
  for (int i = 0; i <= 10; ++i) line.emplace_back(0, 0, 10.0 * i);
  const Mesh m = ewis::make_tube(line, 4, 128);
  expect_closed(m);
  const Mesh c = ewis::make_cylinder(Vector3d(0, 0, 0), Vector3d(0, 0, 100), 4, 128);
  EXPECT_NEAR(area(m), area(c), 1e-3);
  EXPECT_NEAR(volume(m), volume(c), 1e-2);
}

TEST(Primitives, BentTubeFollowsPappus) {
  // A quarter circle of radius 50 in 3D (tilted plane), tube radius 3: volume = pi r^2 * arc length.
  const double bend = 50, r = 3;
  const Vector3d u = Vector3d(1, 1, 0).normalized(), v = Vector3d(0, 0, 1);
  std::vector<Vector3d> line;
  const int n = 400;
  for (int i = 0; i <= n; ++i) {
    const double t = 0.5 * M_PI * i / n;
    line.push_back(Vector3d(3, 4, 5) + bend * (std::cos(t) * u + std::sin(t) * v));
  }
  const Mesh m = ewis::make_tube(line, r, 96);
  expect_closed(m);
  const double arc = 0.5 * M_PI * bend;
  const double vol_true = M_PI * r * r * arc, area_true = 2 * M_PI * r * arc + 2 * M_PI * r * r;
  EXPECT_NEAR(volume(m), vol_true, 3e-3 * vol_true);
  EXPECT_NEAR(area(m), area_true, 3e-3 * area_true);
  // Every vertex lies within r of the circle through the centreline.
  for (const auto& p : m.vertices) {
    const Vector3d q = p.cast<double>() - Vector3d(3, 4, 5);
    const Vector3d in_plane = q.dot(u) * u + q.dot(v) * v;
    const double d = (q - bend * in_plane.normalized()).norm();
    if (in_plane.norm() > 1) {
      EXPECT_LE(d, r + 1e-3);
    }
  }
}

TEST(Primitives, HelicalTubeStaysClosedWithoutTwist) {
  std::vector<Vector3d> line;
  for (int i = 0; i <= 300; ++i) {
    const double t = 4 * M_PI * i / 300;
    line.emplace_back(30 * std::cos(t), 30 * std::sin(t), 5 * t);
  }
  const Mesh m = ewis::make_tube(line, 2, 16);
  expect_closed(m);
  EXPECT_GT(volume(m), 0);
  // Ring vertices stay at radius 2 from their centreline point (frames orthogonal to the tangent).
  for (std::size_t i = 0; i < line.size(); ++i)
    for (int s = 0; s < 16; ++s)
      EXPECT_NEAR((m.vertices[i * 16 + s].cast<double>() - line[i]).norm(), 2.0, 1e-3);
}

TEST(Primitives, DegenerateTubeInputsGiveEmptyMesh) {
  EXPECT_TRUE(ewis::make_tube({}, 1).triangles.empty());
  EXPECT_TRUE(ewis::make_tube({Vector3d(1, 1, 1), Vector3d(1, 1, 1)}, 1).triangles.empty());
}

TEST(Primitives, TransformMovesVertices) {
  Mesh m = ewis::make_box(Vector3d(0, 0, 0), Vector3d(1, 2, 3));
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  transform_mesh(m, rot, Vector3d(10, 20, 30));
  EXPECT_NEAR(volume(m), 6, 1e-4);
  EXPECT_NEAR((m.vertices[0].cast<double>() - Vector3d(10, 20, 30)).norm(), 0, 1e-5);
}

}  // namespace
