#pragma once
// Analytic centrelines for the inspect tests: a turtle that lays straight runs and circular arcs.
#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

namespace ewis::test {

struct Turtle {
  Eigen::Vector3d pos = Eigen::Vector3d::Zero();
  Eigen::Vector3d dir = Eigen::Vector3d::UnitX();
  double step = 1.0;  // spacing of the points laid
  std::vector<Eigen::Vector3d> points{Eigen::Vector3d::Zero()};

  void straight(double len) {
    const int n = std::max(1, int(std::ceil(len / step)));
    const Eigen::Vector3d start = pos;
    for (int i = 1; i <= n; ++i) points.push_back(start + dir * (len * i / n));
    pos = start + dir * len;
  }
  // Arc of radius r turning by angle_deg toward `side` (a unit vector perpendicular to dir).
  void arc(double r, double angle_deg, const Eigen::Vector3d& side) {
    const Eigen::Vector3d axis = dir.cross(side).normalized();
    const Eigen::Vector3d center = pos + side * r;
    const Eigen::Vector3d rel = pos - center;
    const double angle = angle_deg * M_PI / 180.0;
    const int n = std::max(2, int(std::ceil(r * angle / step)));
    for (int i = 1; i <= n; ++i) {
      const Eigen::AngleAxisd rot(angle * i / n, axis);
      points.push_back(center + rot * rel);
    }
    const Eigen::AngleAxisd rot(angle, axis);
    pos = center + rot * rel;
    dir = (rot * dir).normalized();
  }
};

inline std::vector<Eigen::Vector3d> add_noise(std::vector<Eigen::Vector3d> pts, double sigma, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, sigma);
  for (auto& p : pts) p += Eigen::Vector3d(n(rng), n(rng), n(rng));
  return pts;
}

}  // namespace ewis::test
