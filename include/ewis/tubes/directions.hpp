#pragma once
// The search structure's directions (paper 4.2.2): points evenly spread over a sphere; each antipodal pair
// is one candidate cylinder axis through the centre, so a hemisphere of directions is enough. Precomputed
// once (a Fibonacci lattice, the even spread the paper's longitude/colatitude grid approximates).
#include <Eigen/Core>
#include <vector>

namespace ewis {

// About `count` unit directions evenly spread over the hemisphere z >= 0.
std::vector<Eigen::Vector3d> hemisphere_directions(int count);

// Unit directions within `half_angle_deg` of +z, about `spacing_deg` apart (+z itself first).
std::vector<Eigen::Vector3d> cone_directions(double half_angle_deg, double spacing_deg);

// A rotation taking +z to the unit vector `d` (any one; deterministic).
Eigen::Matrix3d rotation_from_z(const Eigen::Vector3d& d);

}  // namespace ewis
