// PCA normals: the eigenvector of the smallest eigenvalue of the neighbourhood covariance, flipped toward the
// viewpoint (the sensor sees the side of a surface that faces it).
#include "ewis/register/point_normals.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>

#include "ewis/core/parallel.hpp"

namespace ewis {

std::vector<Eigen::Vector3f> estimate_point_normals(const KdTree& tree, const PointNormalParams& params,
                                                    std::vector<float>* curvature) {
  const auto& pts = tree.points();
  if (curvature) curvature->assign(pts.size(), 0.0f);
  std::vector<Eigen::Vector3f> normals(pts.size(), Eigen::Vector3f::UnitZ());
  const int k = std::max(3, params.k);
  const double max_sq = params.max_radius_mm > 0 ? params.max_radius_mm * params.max_radius_mm : 0.0;
  parallel_blocks(pts.size(), 512, [&](std::size_t b, std::size_t e) {
    std::vector<Neighbor> nb;
    for (std::size_t i = b; i < e; ++i) {
      tree.knn(pts[i], k, nb);
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      int count = 0;
      for (const Neighbor& n : nb) {
        if (max_sq > 0 && n.distance_sq > max_sq) break;
        mean += pts[n.index].cast<double>();
        ++count;
      }
      Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
      if (count >= 3) {
        mean /= count;
        Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
        for (int j = 0; j < count; ++j) {
          const Eigen::Vector3d d = pts[nb[j].index].cast<double>() - mean;
          cov.noalias() += d * d.transpose();
        }
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
        normal = es.eigenvectors().col(0);
        const double total = es.eigenvalues().sum();
        if (curvature && total > 0) (*curvature)[i] = static_cast<float>(std::max(0.0, es.eigenvalues()(0)) / total);
        if (!normal.allFinite() || normal.norm() < 0.5) normal = Eigen::Vector3d::UnitZ();
      }
      if (normal.dot(params.viewpoint - pts[i].cast<double>()) < 0) normal = -normal;
      normals[i] = normal.normalized().cast<float>();
    }
  });
  return normals;
}

}  // namespace ewis
