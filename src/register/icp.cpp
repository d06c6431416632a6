// Point-to-plane ICP (paper 4.1.2) with Gauss-Newton steps damped Levenberg-Marquardt style, a Cauchy kernel and
// a shrinking correspondence distance. Deterministic: the 6x6 normal equations are summed per fixed block and the
// blocks combined in order (core/parallel.hpp), so any thread count gives the same bits.
#include "ewis/register/icp.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "ewis/core/error.hpp"
#include "ewis/core/parallel.hpp"
#include "ewis/core/robust.hpp"
#include "ewis/search/moving_nearest.hpp"

namespace ewis {
namespace {

constexpr std::size_t kGrain = 2048;

// One correspondence, frozen for an iteration: the source point already mapped by the current pose.
struct Corr {
  Eigen::Vector3d p;  // source point at the current pose, minus the rotation centre
  Eigen::Vector3d n;  // target normal
  double nq = 0.0;    // n . (q - centre)
  bool valid = false;
};

struct Normal6 {
  Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
  double cost = 0.0;
  std::size_t count = 0;
};

struct Cost {
  double cost = 0.0;
  std::size_t count = 0;
};

// Small rigid update about the centre: p -> R(omega) p + v (p relative to the centre).
Eigen::Matrix3d rotation_of(const Eigen::Vector3d& omega) {
  const double angle = omega.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, omega / angle).toRotationMatrix();
}

std::vector<std::uint32_t> all_indices(std::size_t n) {
  std::vector<std::uint32_t> idx(n);
  std::iota(idx.begin(), idx.end(), 0u);
  return idx;
}

std::vector<std::uint32_t> strided(const std::vector<std::uint32_t>& idx, std::size_t max_points) {
  return pick(idx, evenly_strided(idx.size(), max_points));
}

std::vector<double> distance_schedule(const IcpParams& p) {
  const double final_d = std::max(p.final_max_distance_mm, 1e-3);
  double d = p.initial_max_distance_mm > 0 ? p.initial_max_distance_mm : std::max(3.0 * p.expected_error_mm, 10.0);
  d = std::max(d, final_d);
  const double shrink = std::clamp(p.distance_shrink, 0.05, 0.95);
  std::vector<double> out;
  for (int s = 0; s < 60 && d > final_d * 1.0001; ++s, d *= shrink) out.push_back(d);
  out.push_back(final_d);
  return out;
}

void check_inputs(const std::vector<Eigen::Vector3f>& source, const Cloud& target, const KdTree& tree) {
  if (source.empty()) throw InputError("", "registration: the source has no points");
  if (target.empty() || tree.size() == 0) throw InputError("", "registration: the target has no points");
  if (target.normals.size() != target.size())
    throw InputError("", "registration: point-to-plane ICP needs target normals");
}

}  // namespace

double icp_kernel_scale_mm(const IcpParams& params, double max_distance_mm) {
  return std::max(params.kernel_noise_factor * params.noise_mm, max_distance_mm / params.kernel_distance_div);
}

namespace {

// The correspondences of the source points, from the memory when there is one (the same answers).
class Correspondences {
 public:
  // `points`: the source's size; `served`: the source points whose nearest target points are kept from now on
  // (null: those kept so far).
  Correspondences(const KdTree& tree, IcpMemory* memory, std::size_t points, const std::vector<std::uint32_t>* served)
      : tree_(tree), memory_(memory) {
    if (!memory_) return;
    std::vector<std::uint32_t> ids;
    if (served) {
      ids = *served;
      if (!std::is_sorted(ids.begin(), ids.end())) std::sort(ids.begin(), ids.end());
    }
    if (memory_->tree != &tree || memory_->hint.size() != points || !memory_->near) {
      memory_->tree = &tree;
      memory_->hint.assign(points, UINT32_MAX);
      memory_->near = std::make_unique<MovingNearest>(tree, std::move(ids));
    } else if (served) {
      memory_->near->serve(std::move(ids));
    }
  }
  // Source point `id` now at `p`; `moving`: from its nearest target points of last time (fine stages: small
  // steps), else a search from its last correspondence.
  Neighbor nearest(std::uint32_t id, const Eigen::Vector3f& p, float reach, bool moving) const {
    if (!memory_) return tree_.nearest(p, reach, UINT32_MAX);
    std::uint32_t& h = memory_->hint[id];
    const Neighbor nb = moving ? memory_->near->nearest(id, p, reach, h) : tree_.nearest(p, reach, h);
    if (nb.index != UINT32_MAX) h = nb.index;
    return nb;
  }

 private:
  const KdTree& tree_;
  IcpMemory* memory_;
};

RegistrationResult evaluate(const std::vector<Eigen::Vector3f>& source, const Cloud& target, const KdTree& target_tree,
                            const Pose& source_to_target, double inlier_distance_mm,
                            const std::vector<std::uint32_t>& idx, IcpMemory* memory) {
  const Correspondences corr(target_tree, memory, source.size(), nullptr);
  const double max_sq = inlier_distance_mm * inlier_distance_mm;
  const float reach = search_bound_mm(inlier_distance_mm);
  const Eigen::Matrix3d R = source_to_target.linear();
  const Eigen::Vector3d t = source_to_target.translation();
  const Cost sum = parallel_reduce_ordered<Cost>(
      idx.size(), kGrain, Cost{},
      [&](std::size_t b, std::size_t e) {
        Cost c;
        for (std::size_t i = b; i < e; ++i) {
          const Eigen::Vector3d p = R * source[idx[i]].cast<double>() + t;
          const Neighbor nb = corr.nearest(idx[i], p.cast<float>(), reach, true);
          if (nb.index == UINT32_MAX) continue;
          const Eigen::Vector3d q = target.points[nb.index].cast<double>();
          if ((p - q).squaredNorm() > max_sq) continue;
          const double r = target.normals[nb.index].cast<double>().dot(p - q);
          c.cost += r * r;
          ++c.count;
        }
        return c;
      },
      [](Cost a, const Cost& b) {
        a.cost += b.cost;
        a.count += b.count;
        return a;
      });
  RegistrationResult res;
  res.source_to_target = source_to_target;
  res.inliers = sum.count;
  res.inlier_distance_mm = inlier_distance_mm;
  res.fitness = idx.empty() ? 0.0 : static_cast<double>(sum.count) / static_cast<double>(idx.size());
  res.rmse_mm = sum.count ? std::sqrt(sum.cost / static_cast<double>(sum.count)) : 0.0;
  return res;
}

}  // namespace

RegistrationResult evaluate_registration(const std::vector<Eigen::Vector3f>& source, const Cloud& target,
                                         const KdTree& target_tree, const Pose& source_to_target,
                                         double inlier_distance_mm,
                                         const std::vector<std::uint32_t>& source_indices) {
  check_inputs(source, target, target_tree);
  const std::vector<std::uint32_t> idx = source_indices.empty() ? all_indices(source.size()) : source_indices;
  return evaluate(source, target, target_tree, source_to_target, inlier_distance_mm, idx, nullptr);
}

namespace {

// The ICP loop proper; `target`/`target_tree` are the (possibly visibility-culled) correspondence candidates.
Pose icp_loop(const std::vector<Eigen::Vector3f>& source, const Cloud& target, const KdTree& target_tree,
              const Pose& initial_source_to_target, const IcpParams& params,
              const std::vector<std::uint32_t>& all, const ProgressFn& progress, int& total_iterations,
              bool& stage_converged, IcpMemory& memory) {
  const std::vector<double> schedule = distance_schedule(params);
  const double final_d = schedule.back();
  const std::vector<std::uint32_t> coarse = strided(all, params.coarse_max_points);

  Pose T = initial_source_to_target;
  total_iterations = 0;
  stage_converged = false;
  std::vector<Corr> corr;
  // Per source point its last correspondence, and its nearest target points for the fine stages (the coarse ones
  // move too far per step).
  const Correspondences nearest(target_tree, &memory, source.size(), &all);

  for (std::size_t s = 0; s < schedule.size(); ++s) {
    const double d = schedule[s];
    const bool is_coarse = d > (params.coarse_distance_mm > 0 ? params.coarse_distance_mm : 4.0 * final_d);
    const std::vector<std::uint32_t>& idx = is_coarse ? coarse : all;
    const double c = icp_kernel_scale_mm(params, d);
    const double max_sq = d * d;
    const float reach = search_bound_mm(d);
    corr.assign(idx.size(), Corr{});
    stage_converged = false;
    double lambda = params.lm_initial_lambda;

    for (int it = 0; it < params.max_iterations_per_stage && total_iterations < params.max_iterations; ++it) {
      ++total_iterations;
      // Rotation centre: the source centroid at the current pose (conditions the rotation columns of J).
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      const std::size_t stride = std::max<std::size_t>(1, idx.size() / 256);
      std::size_t used = 0;
      for (std::size_t i = 0; i < idx.size(); i += stride, ++used) centre += source[idx[i]].cast<double>();
      centre /= static_cast<double>(used);
      centre = T * centre;

      const Eigen::Matrix3d R = T.linear();
      const Eigen::Vector3d t = T.translation();
      // Correspondences and the IRLS-weighted normal equations in one ordered pass.
      const Normal6 ne = parallel_reduce_ordered<Normal6>(
          idx.size(), kGrain, Normal6{},
          [&](std::size_t b, std::size_t e) {
            Normal6 acc;
            for (std::size_t i = b; i < e; ++i) {
              Corr& k = corr[i];
              const Eigen::Vector3d p = R * source[idx[i]].cast<double>() + t;
              // From the last iteration's answer: after a small step it is at or near the new one.
              const Neighbor nb = nearest.nearest(idx[i], p.cast<float>(), reach, !is_coarse);
              k.valid = false;
              if (nb.index == UINT32_MAX) continue;
              const Eigen::Vector3d q = target.points[nb.index].cast<double>();
              if ((p - q).squaredNorm() > max_sq) continue;
              k.n = target.normals[nb.index].cast<double>();
              k.valid = true;
              k.p = p - centre;
              k.nq = k.n.dot(q - centre);
              const double r = k.n.dot(k.p) - k.nq;
              const double w = cauchy_weight(r, c);
              Eigen::Matrix<double, 6, 1> J;
              J.head<3>() = k.p.cross(k.n);
              J.tail<3>() = k.n;
              acc.H.noalias() += w * J * J.transpose();
              acc.g.noalias() += w * r * J;
              acc.cost += cauchy_rho(r, c);
              ++acc.count;
            }
            return acc;
          },
          [](Normal6 a, const Normal6& b) {
            a.H += b.H;
            a.g += b.g;
            a.cost += b.cost;
            a.count += b.count;
            return a;
          });
      if (ne.count < static_cast<std::size_t>(std::max(params.min_correspondences, 6))) break;

      // Levenberg-Marquardt: damp the Gauss-Newton step until the robust cost (same correspondences) drops.
      bool accepted = false;
      Eigen::Matrix<double, 6, 1> step = Eigen::Matrix<double, 6, 1>::Zero();
      for (int tries = 0; tries < std::max(1, params.lm_max_tries); ++tries) {
        Eigen::Matrix<double, 6, 6> A = ne.H;
        for (int j = 0; j < 6; ++j) A(j, j) += lambda * std::max(ne.H(j, j), 1e-9) + 1e-12;
        step = A.ldlt().solve(-ne.g);
        if (!step.allFinite()) {
          lambda *= 10.0;
          continue;
        }
        const Eigen::Matrix3d dR = rotation_of(step.head<3>());
        const Eigen::Vector3d dv = step.tail<3>();
        const Cost trial = parallel_reduce_ordered<Cost>(
            corr.size(), kGrain, Cost{},
            [&](std::size_t b, std::size_t e) {
              Cost acc;
              for (std::size_t i = b; i < e; ++i) {
                const Corr& k = corr[i];
                if (!k.valid) continue;
                const double r = k.n.dot(dR * k.p + dv) - k.nq;
                acc.cost += cauchy_rho(r, c);
              }
              return acc;
            },
            [](Cost a, const Cost& b) {
              a.cost += b.cost;
              return a;
            });
        if (trial.cost <= ne.cost) {
          accepted = true;
          lambda = std::max(lambda * 0.1, 1e-12);
          break;
        }
        lambda *= 10.0;
      }
      if (!accepted) {  // no descent left at this distance: the stage sits at its minimum
        stage_converged = true;
        break;
      }
      const Eigen::Matrix3d dR = rotation_of(step.head<3>());
      Pose delta = Pose::Identity();
      delta.linear() = dR;
      delta.translation() = centre + step.tail<3>() - dR * centre;
      T = delta * T;
      // Re-orthonormalise (repeated products drift by ~1e-16 per step).
      const Eigen::Quaterniond qn(T.linear());
      T.linear() = qn.normalized().toRotationMatrix();

      // Coarse stages only need to hand over a pose well inside the next distance: their test scales with it.
      const double scale = s + 1 < schedule.size() ? std::max(1.0, d * 1e-3 / params.converge_translation_mm) : 1.0;
      if (step.head<3>().norm() * 180.0 / M_PI < scale * params.converge_rotation_deg &&
          step.tail<3>().norm() < scale * params.converge_translation_mm) {
        stage_converged = true;
        break;
      }
    }
    if (progress) progress("register", static_cast<double>(s + 1) / static_cast<double>(schedule.size()));
  }

  return T;
}

}  // namespace

RegistrationResult align_point_to_plane(const std::vector<Eigen::Vector3f>& source, const Cloud& target,
                                        const KdTree& target_tree, const Pose& initial_source_to_target,
                                        const IcpParams& params, const std::vector<std::uint32_t>& source_indices,
                                        const ProgressFn& progress, IcpMemory* memory) {
  check_inputs(source, target, target_tree);
  const std::vector<std::uint32_t> all = source_indices.empty() ? all_indices(source.size()) : source_indices;
  const std::vector<std::uint32_t> used = strided(all, params.max_points);
  int iterations = 0;
  bool converged = false;
  Pose T;
  IcpMemory own;
  IcpMemory* learnt = nullptr;  // what the loop learnt on target_tree, when it ran on it
  if (params.use_source_viewpoint) {
    // Only target faces the sensor can see from (about) the initial pose take part: keep points whose normal
    // is at most ~100 deg from the direction to the sensor (grazing walls stay, a plate's far side goes).
    const Eigen::Vector3d eye = initial_source_to_target * params.source_viewpoint;
    const std::vector<std::uint32_t> visible = parallel_select(target.size(), [&](std::size_t i) {
      const Eigen::Vector3d to_eye = eye - target.points[i].cast<double>();
      return target.normals[i].cast<double>().dot(to_eye) > -0.2 * to_eye.norm();
    });
    if (visible.size() < 3) throw ProcessingError("registration: no CAD surface faces the sensor at the initial pose");
    const Cloud seen = select(target, visible);
    const KdTree seen_tree(seen.points);
    IcpMemory on_seen;  // of another tree than target_tree
    T = icp_loop(source, seen, seen_tree, initial_source_to_target, params, used, progress, iterations, converged,
                 on_seen);
  } else {
    learnt = memory ? memory : &own;
    T = icp_loop(source, target, target_tree, initial_source_to_target, params, used, progress, iterations, converged,
                 *learnt);
  }
  // Fitness over every source point at the final pose: the last iteration's neighbours answer most of them.
  RegistrationResult res =
      evaluate(source, target, target_tree, T, distance_schedule(params).back(), all, learnt);
  res.iterations = iterations;
  res.converged = converged;
  return res;
}

}  // namespace ewis
