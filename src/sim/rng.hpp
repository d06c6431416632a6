#pragma once
// Small portable random numbers for the simulator: the same bits on every platform and standard library
// (std::uniform_real_distribution and std::normal_distribution are implementation-defined), so a seed
// gives byte-identical scenes everywhere. Every item (pixel, scene, outlier) seeds its own generator.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>

namespace ewis::sim {

inline std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// Seed of item k of a stream seeded by `seed` (and a stream tag, so streams do not repeat each other).
inline std::uint64_t mix(std::uint64_t seed, std::uint64_t k, std::uint64_t tag = 0) {
  return splitmix64(splitmix64(seed ^ (tag * 0xD6E8FEB86659FD93ull)) + k);
}

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : s_(splitmix64(seed)) {}
  std::uint64_t next() {
    s_ += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = s_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return (next() >> 11) * (1.0 / 9007199254740992.0); }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  int integer(int lo, int hi_inclusive) {
    return lo + static_cast<int>(next() % static_cast<std::uint64_t>(hi_inclusive - lo + 1));
  }
  bool chance(double p) { return uniform() < p; }
  double normal() {  // Box-Muller, no cached state
    const double u1 = 1.0 - uniform();
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }
  Eigen::Vector3d unit_vector() {
    const double z = uniform(-1.0, 1.0), phi = uniform(0.0, 2.0 * M_PI), r = std::sqrt(1.0 - z * z);
    return {r * std::cos(phi), r * std::sin(phi), z};
  }

 private:
  std::uint64_t s_;
};

}  // namespace ewis::sim
