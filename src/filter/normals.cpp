// Normals and surface variation by PCA over k nearest or radius neighbourhoods.
#include "ewis/filter/normals.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

#include "ewis/core/parallel.hpp"

namespace ewis {
namespace {

struct NormalAt {
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();
  float curvature = 0.0f;
};

NormalAt normal_at(const KdTree& tree, std::uint32_t i, const NormalParams& params, std::vector<Neighbor>& nb) {
  NormalAt out;
  const auto& pts = tree.points();
  const Eigen::Vector3f& p = pts[i];
  if (params.radius_mm > 0) {
    tree.radius(p, static_cast<float>(params.radius_mm), nb);
    if (params.max_neighbors > 0 && nb.size() > static_cast<std::size_t>(params.max_neighbors))
      nb.resize(static_cast<std::size_t>(params.max_neighbors));  // sorted: keeps the nearest
  } else {
    tree.knn(p, params.k, nb);
  }
  if (nb.size() < 3) return out;

  // Covariance about the centroid, in double, with the point as a local origin against cancellation.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Neighbor& q : nb) mean += (pts[q.index] - p).cast<double>();
  mean /= static_cast<double>(nb.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Neighbor& q : nb) {
    const Eigen::Vector3d d = (pts[q.index] - p).cast<double>() - mean;
    cov.noalias() += d * d.transpose();
  }
  cov /= static_cast<double>(nb.size());

  // the iterative solver: computeDirect was measured barely faster here and loses accuracy near silhouettes
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  if (eig.info() != Eigen::Success) return out;
  const Eigen::Vector3d lambda = eig.eigenvalues().cwiseMax(0.0);  // increasing
  const double trace = lambda.sum();
  if (!(trace > 0) || !(lambda(1) > 1e-12 * trace)) return out;  // all coincident or collinear: no plane
  Eigen::Vector3d n = eig.eigenvectors().col(0).normalized();
  // orient towards the viewpoint (as PCL flipNormalTowardsViewpoint): the sensor sees the side facing it
  if (n.dot((params.viewpoint - p).cast<double>()) < 0) n = -n;
  out.normal = n.cast<float>();
  out.curvature = static_cast<float>(lambda(0) / trace);
  return out;
}

template <class IndexOf>
std::vector<Eigen::Vector3f> estimate(const KdTree& tree, std::size_t m, const IndexOf& index_of,
                                      const NormalParams& params, std::vector<float>* curvature) {
  std::vector<Eigen::Vector3f> normals(m, Eigen::Vector3f::Zero());
  if (curvature) curvature->assign(m, 0.0f);
  const std::size_t n = tree.size();
  parallel_blocks(m, 512, [&](std::size_t b, std::size_t e) {
    std::vector<Neighbor> nb;
    for (std::size_t j = b; j < e; ++j) {
      const std::uint32_t i = index_of(j);
      if (i >= n) continue;
      const NormalAt r = normal_at(tree, i, params, nb);
      normals[j] = r.normal;
      if (curvature) (*curvature)[j] = r.curvature;
    }
  });
  return normals;
}

}  // namespace

std::vector<Eigen::Vector3f> estimate_normals(const KdTree& tree, const NormalParams& params,
                                              std::vector<float>* curvature) {
  // in the tree's spatial order for cache locality; each result goes to its point's slot
  const auto& order = tree.spatial_order();
  std::vector<Eigen::Vector3f> normals(tree.size(), Eigen::Vector3f::Zero());
  if (curvature) curvature->assign(tree.size(), 0.0f);
  parallel_blocks(order.size(), 512, [&](std::size_t b, std::size_t e) {
    std::vector<Neighbor> nb;
    for (std::size_t j = b; j < e; ++j) {
      const NormalAt r = normal_at(tree, order[j], params, nb);
      normals[order[j]] = r.normal;
      if (curvature) (*curvature)[order[j]] = r.curvature;
    }
  });
  return normals;
}

std::vector<Eigen::Vector3f> estimate_normals(const KdTree& tree, const std::vector<std::uint32_t>& indices,
                                              const NormalParams& params, std::vector<float>* curvature) {
  return estimate(tree, indices.size(), [&](std::size_t j) { return indices[j]; }, params, curvature);
}

}  // namespace ewis
