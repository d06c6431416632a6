// The weakest direction of translation of a pose, and the fitness probed along it (see weak_direction.hpp).
#include "ewis/register/weak_direction.hpp"

#include <Eigen/Eigenvalues>
#include <limits>

#include "ewis/register/icp.hpp"

namespace ewis {

WeakDirection weakest_translation(const std::vector<Eigen::Vector3f>& source, const std::vector<std::uint32_t>& indices,
                                  const Cloud& target, const KdTree& target_tree, const Pose& source_to_target,
                                  double distance_mm) {
  WeakDirection out;
  if (target.normals.size() != target.size()) return out;
  Eigen::Matrix3d N = Eigen::Matrix3d::Zero();
  const float reach = static_cast<float>(distance_mm);
  for (std::uint32_t i : indices) {
    const Eigen::Vector3f p = (source_to_target * source[i].cast<double>()).cast<float>();
    const Neighbor nb = target_tree.nearest(p, reach, std::numeric_limits<std::uint32_t>::max());
    if (nb.index == std::numeric_limits<std::uint32_t>::max()) continue;
    const Eigen::Vector3d n = target.normals[nb.index].cast<double>();
    N.noalias() += n * n.transpose();
    ++out.matched;
  }
  if (out.matched < 6) return out;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(N);
  const double largest = es.eigenvalues()(2);
  if (!(largest > 0.0)) return out;
  out.ratio = std::max(0.0, es.eigenvalues()(0)) / largest;
  out.direction = es.eigenvectors().col(0).normalized();
  return out;
}

double best_offset_along(const std::vector<Eigen::Vector3f>& source, const std::vector<std::uint32_t>& indices,
                         const Cloud& target, const KdTree& target_tree, const Pose& source_to_target,
                         const Eigen::Vector3d& direction, double inlier_distance_mm, const WeakDirectionParams& params) {
  if (indices.empty() || !(params.step_mm > 0.0)) return 0.0;
  const auto fitness_at = [&](double offset_mm) {
    Pose moved = source_to_target;
    moved.translation() += offset_mm * direction;
    return evaluate_registration(source, target, target_tree, moved, inlier_distance_mm, indices).fitness;
  };
  const double at_pose = fitness_at(0.0);
  double best = at_pose, best_offset = 0.0;
  for (const double sign : {1.0, -1.0}) {
    double previous = at_pose;
    for (int k = 1; k * params.step_mm <= params.reach_mm + 1e-9; ++k) {
      const double offset = sign * k * params.step_mm;
      const double f = fitness_at(offset);
      if (f < previous) break;  // a flat stretch is crossed: the faces that fix the pose may lie beyond it
      previous = f;
      if (f > best) {
        best = f;
        best_offset = offset;
      }
    }
  }
  return best >= at_pose + params.min_gain ? best_offset : 0.0;
}

}  // namespace ewis
