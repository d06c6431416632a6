#pragma once
// Closed triangle meshes of analytic shapes, for the simulator's scenes and for tests.
#include <Eigen/Core>
#include <vector>

namespace ewis {

struct Mesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3i> triangles;  // outward-facing (counter-clockwise seen from outside)
};

// Axis-aligned box between min and max corners.
Mesh make_box(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& max_corner);
// UV sphere.
Mesh make_sphere(const Eigen::Vector3d& center, double radius_mm, int segments = 48, int rings = 24);
// Capped cylinder from a to b.
Mesh make_cylinder(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius_mm, int segments = 32);
// Torus around `axis` through `center`: major radius R (centre of tube), minor radius r.
Mesh make_torus(const Eigen::Vector3d& center, const Eigen::Vector3d& axis, double major_radius_mm,
                double minor_radius_mm, int major_segments = 96, int minor_segments = 24);
// A tube of constant radius swept along a polyline centreline (rotation-minimising frames, so no twist),
// with flat end caps. Consecutive centreline points should be closer than the radius for smooth bends.
Mesh make_tube(const std::vector<Eigen::Vector3d>& centerline, double radius_mm, int segments = 24);

// Applies a rigid transform to every vertex (a mirror also reverses the winding: the mesh stays outward).
void transform_mesh(Mesh& mesh, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation);

}  // namespace ewis
