// FPFH (Rusu, Blodow, Beetz 2009, "Fast Point Feature Histograms for 3D registration"), following PCL's
// computePairFeatures / FPFHEstimation: SPFH of each point over its radius neighbours, then
// FPFH(p) = SPFH(p) + normalised sum_k SPFH(p_k) / |p - p_k|^2.
#include "ewis/register/fpfh.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

#include "ewis/core/parallel.hpp"

namespace ewis {
namespace {

constexpr int kBins = 11;

// Darboux-frame angles of a point pair (PCL's computePairFeatures); false for a degenerate pair.
bool pair_features(const Eigen::Vector3f& p1, const Eigen::Vector3f& n1, const Eigen::Vector3f& p2,
                   const Eigen::Vector3f& n2, float& f1, float& f2, float& f3) {
  Eigen::Vector3f dp = p2 - p1;
  const float f4 = dp.norm();
  if (f4 == 0.0f) return false;
  Eigen::Vector3f u = n1, m = n2;
  const float a1 = n1.dot(dp) / f4, a2 = n2.dot(dp) / f4;
  // The same point of the pair is the frame's origin whichever way round the pair comes.
  if (std::acos(std::min(1.0f, std::fabs(a1))) > std::acos(std::min(1.0f, std::fabs(a2)))) {
    u = n2;
    m = n1;
    dp = -dp;
    f3 = -a2;
  } else {
    f3 = a1;
  }
  Eigen::Vector3f v = dp.cross(u);
  const float vn = v.norm();
  if (vn == 0.0f) return false;
  v /= vn;
  const Eigen::Vector3f w = u.cross(v);
  f2 = v.dot(m);
  // Antiparallel normals (a plate's two faces: common in CAD) put f1 at +-pi, the two end bins, by the sign of a
  // rounded zero: snap that zero so both views of the pair fall in the same bin.
  const float y = w.dot(m);
  f1 = std::atan2(std::abs(y) < 1e-6f ? 0.0f : y, u.dot(m));
  return true;
}

int bin_of(float value, float lo, float hi) {
  const int b = static_cast<int>(std::floor(kBins * (value - lo) / (hi - lo)));
  return std::clamp(b, 0, kBins - 1);
}

}  // namespace

std::vector<Fpfh> compute_fpfh(const KdTree& tree, const std::vector<Eigen::Vector3f>& normals,
                               const FpfhParams& params) {
  const auto& pts = tree.points();
  const std::size_t n = pts.size();
  const float radius = static_cast<float>(params.radius_mm);
  const std::size_t max_nb = std::max<std::size_t>(params.max_neighbors, 2);

  // Neighbour lists (kept for the weighting pass), nearest first, without the point itself.
  std::vector<std::vector<Neighbor>> neighbours(n);
  std::vector<Fpfh> spfh(n);
  parallel_blocks(n, 256, [&](std::size_t b, std::size_t e) {
    std::vector<Neighbor> nb;
    for (std::size_t i = b; i < e; ++i) {
      tree.radius(pts[i], radius, nb);
      auto& mine = neighbours[i];
      mine.clear();
      for (const Neighbor& x : nb) {
        if (x.index == i) continue;
        mine.push_back(x);
        if (mine.size() >= max_nb) break;
      }
      Fpfh h{};
      if (!mine.empty()) {
        const float incr = 100.0f / static_cast<float>(mine.size());
        for (const Neighbor& x : mine) {
          float f1, f2, f3;
          if (!pair_features(pts[i], normals[i], pts[x.index], normals[x.index], f1, f2, f3)) continue;
          h[bin_of(f1, -static_cast<float>(M_PI), static_cast<float>(M_PI))] += incr;
          h[kBins + bin_of(f2, -1.0f, 1.0f)] += incr;
          h[2 * kBins + bin_of(f3, -1.0f, 1.0f)] += incr;
        }
      }
      spfh[i] = h;
    }
  });

  std::vector<Fpfh> out(n);
  parallel_blocks(n, 256, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      Fpfh acc{};
      double sum[3] = {0, 0, 0};
      for (const Neighbor& x : neighbours[i]) {
        if (x.distance_sq <= 0.0f) continue;
        const float w = 1.0f / x.distance_sq;
        const Fpfh& s = spfh[x.index];
        for (int j = 0; j < 3 * kBins; ++j) {
          const float v = s[j] * w;
          acc[j] += v;
          sum[j / kBins] += v;
        }
      }
      for (int j = 0; j < 3 * kBins; ++j) {
        const double part = sum[j / kBins];
        const float scale = part > 0 ? static_cast<float>(100.0 / part) : 0.0f;
        acc[j] = acc[j] * scale + spfh[i][j];
      }
      out[i] = acc;
    }
  });
  return out;
}

}  // namespace ewis
