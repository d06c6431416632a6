#pragma once
// Synthetic clouds with known truth for the filter tests.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace ewis::test {

// nx x ny grid at spacing s in the plane z = z0, x fastest; optional in-plane jitter (uniform +-jitter)
// and normal noise (gaussian sigma) from a fixed seed.
inline std::vector<Eigen::Vector3f> plane_grid(int nx, int ny, float s, float z0 = 0.f, float jitter = 0.f,
                                               float noise_sigma = 0.f, std::uint32_t seed = 1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  std::normal_distribution<float> g(0.f, 1.f);
  std::vector<Eigen::Vector3f> pts;
  pts.reserve(static_cast<std::size_t>(nx) * ny);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      Eigen::Vector3f p(i * s, j * s, z0);
      if (jitter > 0) {
        p.x() += jitter * u(rng);
        p.y() += jitter * u(rng);
      }
      if (noise_sigma > 0) p.z() += noise_sigma * g(rng);
      pts.push_back(p);
    }
  return pts;
}

// Points on a sphere by the Fibonacci spiral (nearly uniform).
inline std::vector<Eigen::Vector3f> fibonacci_sphere(const Eigen::Vector3f& centre, float radius, int n) {
  std::vector<Eigen::Vector3f> pts;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n;
    const double r = std::sqrt(1.0 - z * z);
    const double phi = golden * i;
    pts.push_back(centre + radius * Eigen::Vector3f(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z)));
  }
  return pts;
}

}  // namespace ewis::test
