#pragma once
// Normals of a point cloud by PCA of the k nearest neighbours (for cloud-to-cloud registration and FPFH),
// kept inside the register stage so it does not wait on filter/. Oriented toward a viewpoint (PCL's rule).
#include <Eigen/Core>
#include <vector>

#include "ewis/search/kdtree.hpp"

namespace ewis {

struct PointNormalParams {
  int k = 16;                                          // neighbours (including the point itself)
  double max_radius_mm = 0.0;                          // > 0: ignore neighbours farther than this
  Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero(); // normals point toward it (the sensor: scan origin)
};

// One unit normal per tree point; (0,0,1) oriented where fewer than 3 neighbours are found. Deterministic.
// `curvature`, when given, receives the surface variation l0 / (l0 + l1 + l2) (0 on a plane, 0 where undefined).
std::vector<Eigen::Vector3f> estimate_point_normals(const KdTree& tree, const PointNormalParams& params = {},
                                                    std::vector<float>* curvature = nullptr);

}  // namespace ewis
