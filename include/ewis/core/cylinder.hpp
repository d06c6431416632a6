#pragma once
// A finite cylinder (a sub-cable of paper 4.2.3): axis from start to end, radius in mm.
#include <Eigen/Core>

namespace ewis {

struct Cylinder {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d end = Eigen::Vector3d::UnitZ();
  double radius_mm = 1.0;

  double length_mm() const { return (end - start).norm(); }
  Eigen::Vector3d axis() const { return (end - start).normalized(); }
};

// Distance from p to the infinite axis line of c.
double distance_to_axis(const Cylinder& c, const Eigen::Vector3d& p);

// Distance from p to the axis segment of c (clamped to the ends).
double distance_to_segment(const Cylinder& c, const Eigen::Vector3d& p);

}  // namespace ewis
