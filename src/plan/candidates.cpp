// Paper 3.2: candidate viewpoints evenly spread over a sphere of radius rho around the element's centre of mass.
#include "ewis/plan/candidates.hpp"

#include <cmath>
#include <string>

#include "ewis/core/error.hpp"

namespace ewis {
namespace {

constexpr double kEps = 1e-9;
constexpr std::size_t kMaxCandidates = 1000000;

void check_common(const CandidateParams& p) {
  if (!(p.step_deg > 0.0) || !std::isfinite(p.step_deg)) throw InputError("", "--step must be a positive angle");
  if (!(p.radius_mm > 0.0) || !std::isfinite(p.radius_mm)) throw InputError("", "--radius must be positive");
}

}  // namespace

std::vector<double> theta_samples_deg(const CandidateParams& p) {
  check_common(p);
  const double range = p.theta_max_deg - p.theta_min_deg;
  if (!std::isfinite(range) || range < 0.0) throw InputError("", "--theta range must be MIN,MAX with MIN <= MAX");
  const bool full_circle = range >= 360.0 - kEps;
  std::size_t n = 0;
  if (full_circle) {
    // 360 is theta_min again: cover [min, min + 360).
    n = static_cast<std::size_t>(std::ceil(360.0 / p.step_deg - kEps));
  } else {
    n = static_cast<std::size_t>(std::floor(range / p.step_deg + kEps)) + 1;
  }
  if (n == 0 || n > kMaxCandidates) throw InputError("", "--step gives too many candidates");
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = p.theta_min_deg + static_cast<double>(i) * p.step_deg;
  return out;
}

std::vector<double> phi_samples_deg(const CandidateParams& p) {
  check_common(p);
  if (!(p.phi_min_deg >= 0.0) || !(p.phi_max_deg <= 180.0) || !(p.phi_min_deg <= p.phi_max_deg))
    throw InputError("", "--phi range must be MIN,MAX with 0 <= MIN <= MAX <= 180");
  const double range = p.phi_max_deg - p.phi_min_deg;
  const auto cells = static_cast<std::size_t>(std::floor(range / p.step_deg + kEps));
  if (cells == 0) return {0.5 * (p.phi_min_deg + p.phi_max_deg)};
  if (cells > kMaxCandidates) throw InputError("", "--step gives too many candidates");
  // Cell centres, the grid centred in the range (paper 3.2: "evenly distributed on the sphere surface").
  const double start = p.phi_min_deg + 0.5 * (range - static_cast<double>(cells) * p.step_deg);
  std::vector<double> out(cells);
  for (std::size_t i = 0; i < cells; ++i) out[i] = start + (static_cast<double>(i) + 0.5) * p.step_deg;
  return out;
}

Pose candidate_pose(const Eigen::Vector3d& position, const Eigen::Vector3d& target) {
  const Eigen::Vector3d forward = (target - position).normalized();
  // Roll rule: world +z up in the image; near vertical views (|cos| > 0.999, i.e. within ~2.6 deg), world +y.
  const Eigen::Vector3d up = std::abs(forward.z()) > 0.999 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
  return look_at(position, target, up);
}

CandidateGrid make_candidates(const Eigen::Vector3d& center, const CandidateParams& p) {
  CandidateGrid grid;
  grid.theta_deg = theta_samples_deg(p);
  grid.phi_deg = phi_samples_deg(p);
  if (grid.theta_deg.size() * grid.phi_deg.size() > kMaxCandidates)
    throw InputError("", "--step gives too many candidates (" +
                             std::to_string(grid.theta_deg.size() * grid.phi_deg.size()) + ")");
  grid.candidates.reserve(grid.theta_deg.size() * grid.phi_deg.size());
  for (std::size_t ip = 0; ip < grid.phi_deg.size(); ++ip) {
    const double phi = grid.phi_deg[ip] * M_PI / 180.0;
    for (std::size_t it = 0; it < grid.theta_deg.size(); ++it) {
      const double theta = grid.theta_deg[it] * M_PI / 180.0;
      Candidate c;
      c.theta_deg = grid.theta_deg[it];
      c.phi_deg = grid.phi_deg[ip];
      c.theta_index = static_cast<int>(it);
      c.phi_index = static_cast<int>(ip);
      c.target = center;
      c.position = center + p.radius_mm * Eigen::Vector3d(std::sin(phi) * std::cos(theta),
                                                          std::sin(phi) * std::sin(theta), std::cos(phi));
      c.camera_to_cad = candidate_pose(c.position, c.target);
      grid.candidates.push_back(c);
    }
  }
  return grid;
}

}  // namespace ewis
