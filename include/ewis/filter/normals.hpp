#pragma once
// Surface normals by local PCA (as PCL's NormalEstimation): the normal is the eigenvector of the smallest
// eigenvalue of the neighbourhood's covariance, oriented towards the viewpoint (the sensor sees the side of
// the surface that faces it). Curvature is the surface variation lambda0 / (lambda0 + lambda1 + lambda2).
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "ewis/search/kdtree.hpp"

namespace ewis {

struct NormalParams {
  int k = 16;                  // neighbours (the point itself included) when radius_mm is 0
  double radius_mm = 0.0;      // > 0: all points within this radius instead of k nearest
  int max_neighbors = 256;     // radius mode: at most this many nearest are used (bounds the work)
  Eigen::Vector3f viewpoint = Eigen::Vector3f::Zero();  // mm; origin = the sensor in its own frame
};

// One normal per tree point, unit length; (0, 0, 0) where undefined (fewer than 3 neighbours, a degenerate
// neighbourhood, or a non-finite point). `curvature`, when given, receives the surface variation
// (0 on a plane, 1/3 for isotropic scatter; 0 where undefined). Parallel and deterministic.
std::vector<Eigen::Vector3f> estimate_normals(const KdTree& tree, const NormalParams& params,
                                              std::vector<float>* curvature = nullptr);

// The same for the tree points at `indices` only (neighbours still come from the whole tree); the output
// follows the order of `indices`.
std::vector<Eigen::Vector3f> estimate_normals(const KdTree& tree, const std::vector<std::uint32_t>& indices,
                                              const NormalParams& params, std::vector<float>* curvature = nullptr);

}  // namespace ewis
