#pragma once
// Analytic solids of the simulated scenes (boxes, spheres, capped cylinders, tori) with exact distances,
// so the truth's gaps are surface-to-surface distances of the ideal geometry, not of a tessellation.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "ewis/core/pose.hpp"
#include "ewis/scene/primitives.hpp"
#include "ewis/sim/route.hpp"

namespace ewis::sim {

struct Shape {
  enum class Kind { Box, Sphere, Cylinder, Torus };
  Kind kind = Kind::Box;
  Pose frame = Pose::Identity();  // shape frame -> CAD; the shape is centred at its frame's origin
  Eigen::Vector3d half_extents_mm = Eigen::Vector3d::Ones();  // Box
  double radius_mm = 1.0;        // Sphere, Cylinder (axis z), Torus tube (minor radius)
  double length_mm = 1.0;        // Cylinder: from z = -length/2 to +length/2
  double major_radius_mm = 1.0;  // Torus: around the z axis
};

Shape make_box_shape(const Pose& frame, const Eigen::Vector3d& half_extents_mm);
Shape make_aabb_shape(const Eigen::Vector3d& min_corner, const Eigen::Vector3d& max_corner);
Shape make_sphere_shape(const Eigen::Vector3d& center, double radius_mm);
Shape make_cylinder_shape(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius_mm);
Shape make_torus_shape(const Eigen::Vector3d& center, const Eigen::Vector3d& axis, double major_radius_mm,
                       double minor_radius_mm);

// Euclidean distance from p to the solid (0 inside).
double distance_to_shape(const Shape& shape, const Eigen::Vector3d& p);
// Triangle mesh of the shape (fine enough that its surface is within ~0.01 of the radius of the ideal one).
Mesh shape_mesh(const Shape& shape);
// Appends b to a (vertex indices shifted).
void append_mesh(Mesh& a, const Mesh& b);

// A solid made of shapes (one CAD element).
struct Solid {
  std::vector<Shape> shapes;
  double distance(const Eigen::Vector3d& p) const;  // to the union
  Mesh mesh() const;
};

// A cable's tube: constant radius along a route.
struct Tube {
  const Route* route = nullptr;
  double radius_mm = 1.0;
};

struct GapResult {
  double gap_mm = 0.0;                                   // surface to surface (negative: overlap)
  Eigen::Vector3d on_cable = Eigen::Vector3d::Zero();    // centreline point of the closest approach
  Eigen::Vector3d on_other = Eigen::Vector3d::Zero();    // closest point's centreline/ surface point estimate
  double s_mm = 0.0;                                     // arc length of on_cable
};

// Exact (to ~1e-6 mm) least surface-to-surface distance between a tube and a solid: a 0.5 mm scan of the
// route, then golden-section refinement of the best candidates on the analytic route.
GapResult tube_solid_gap(const Tube& tube, const Solid& solid);
// Same between two tubes (the distance of their centrelines minus both radii), refined alternately.
GapResult tube_tube_gap(const Tube& a, const Tube& b);

}  // namespace ewis::sim
