// The registration's last step on the CAD's exact surface (see the header).
#include "ewis/register/surface_refine.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "ewis/core/parallel.hpp"

namespace ewis {
namespace {

constexpr std::size_t kGrain = 1024;

struct Normal6 {
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
  double cost = 0.0, squares = 0.0;
  std::size_t count = 0;
};

Normal6 add(Normal6 a, const Normal6& b) {
  a.H += b.H;
  a.g += b.g;
  a.cost += b.cost;
  a.squares += b.squares;
  a.count += b.count;
  return a;
}

}  // namespace

RegistrationResult refine_on_surface(const std::vector<Eigen::Vector3f>& source, const SurfaceIndex& surface,
                                     const Pose& start, const SurfaceRefineParams& params,
                                     const std::vector<std::uint32_t>& indices) {
  RegistrationResult res;
  res.source_to_target = start;
  res.inlier_distance_mm = params.max_distance_mm;
  const std::size_t n = indices.empty() ? source.size() : indices.size();
  if (n == 0 || surface.empty()) return res;
  auto point = [&](std::size_t i) { return source[indices.empty() ? i : indices[i]].cast<double>(); };
  const double c = params.kernel_mm;
  Pose T = start;
  // The normal equations about the centre of the points (conditioning), summed per fixed block in order.
  auto normal_equations = [&](const Pose& pose, const Eigen::Vector3d& centre) {
    return parallel_reduce_ordered<Normal6>(
        n, kGrain, Normal6{},
        [&](std::size_t b, std::size_t e) {
          Normal6 acc;
          // Runs of consecutive points (neighbours in a scan in leaf or raster order): the surface index is walked
          // once per run, each point getting its own closest point.
          surface.closest_each(b, e, params.max_distance_mm, [&](std::size_t i) { return pose * point(i); },
                               [&](std::size_t, const Eigen::Vector3d& p, const SurfacePoint& s) {
            if (!s.found()) return;
            const Eigen::Vector3d d = p - s.point;
            const double r = d.norm();
            ++acc.count;
            acc.squares += r * r;
            acc.cost += 0.5 * c * c * std::log1p((r / c) * (r / c));
            if (!(r > 1e-9)) return;  // on the surface: no direction, no pull
            const Eigen::Vector3d u = d / r;
            Eigen::Matrix<double, 6, 1> J;
            J.head<3>() = (p - centre).cross(u);
            J.tail<3>() = u;
            const double w = 1.0 / (1.0 + (r / c) * (r / c));
            acc.H.noalias() += w * J * J.transpose();
            acc.g.noalias() += w * r * J;
          });
          return acc;
        },
        add);
  };
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) centre += point(i);
  centre = start * (centre / static_cast<double>(n));
  Normal6 ne = normal_equations(T, centre);
  for (int it = 0; it < params.max_iterations && ne.count >= 6; ++it) {
    Eigen::Matrix<double, 6, 6> A = ne.H;
    for (int j = 0; j < 6; ++j) A(j, j) += 1e-9 * std::max(ne.H(j, j), 1e-9);
    const Eigen::Matrix<double, 6, 1> step = A.ldlt().solve(-ne.g);
    if (!step.allFinite()) break;
    const double angle = step.head<3>().norm();
    const Eigen::Matrix3d dR = angle > 1e-15 ? Eigen::AngleAxisd(angle, step.head<3>() / angle).toRotationMatrix()
                                             : Eigen::Matrix3d::Identity();
    Pose delta = Pose::Identity();
    delta.linear() = dR;
    delta.translation() = centre + step.tail<3>() - dR * centre;
    Pose trial = delta * T;
    trial.linear() = Eigen::Quaterniond(trial.linear()).normalized().toRotationMatrix();
    const Normal6 next = normal_equations(trial, centre);
    if (next.count < 6) break;
    if (next.cost > ne.cost) {  // no descent left: the pose sits at its minimum
      res.converged = true;
      break;
    }
    T = trial;
    ne = next;
    ++res.iterations;
    if (angle * 180.0 / M_PI < params.converge_rotation_deg && step.tail<3>().norm() < params.converge_translation_mm) {
      res.converged = true;
      break;
    }
  }
  res.source_to_target = T;
  res.inliers = ne.count;
  res.fitness = static_cast<double>(ne.count) / static_cast<double>(n);
  res.rmse_mm = ne.count ? std::sqrt(ne.squares / static_cast<double>(ne.count)) : 0.0;
  return res;
}

}  // namespace ewis
