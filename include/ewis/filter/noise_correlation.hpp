#pragma once
// How much neighbouring points' noise moves together. A stereo sensor matches windows of several pixels, so its
// depth errors are smooth over a few pixels: a fit over N points is then known far less well than N independent
// errors would say (its variance is `inflation` times larger), and a likelihood ratio between two fits reads
// `inflation` times too high. Measured from the scan alone: residuals of local quadric surfaces on smooth patches,
// their variogram by lag, and the correlation summed over the neighbours a point has (docs/inspect.md "Noise that
// neighbouring points share").
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "ewis/core/cloud.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis {

struct NoiseCorrelationParams {
  std::size_t patches = 200;           // seeds evenly strided along the tree's leaf order
  double patch_radius = 24.0;          // x resolution: the quadric's patch (12 mm at 0.5 mm)
  double max_lag = 10.0;               // x resolution: rho's lags, in bins of one resolution
  std::size_t max_patch_points = 160;  // evenly strided within the patch (the pairs cost its square)
  std::size_t min_patch_points = 40;
  double trim_sigmas = 3.0;            // residuals beyond this many robust sigmas (outliers the filter kept): left out
  double max_patch_sigma_ratio = 1.5;  // patches over this x the median sigma are no smooth surface (edges, thin cables)
  double max_curvature_times_radius = 0.35;  // ... nor those curving more (a cylinder of 34 mm radius at 12 mm)
  // A quartic's residual variance under this x the quadric's: a shape the quadric misses, left out (ridges 5 mm in
  // radius: 0.003-0.004; noise smoothed over 2 pixels 0.64-0.92 at the 5th-75th percentiles; independent ~1).
  double min_quartic_variance_ratio = 0.5;
  std::size_t min_patches = 30;        // fewer smooth patches: no estimate (inflation 1)
  double min_sigma_mm = 0.01;          // nor where the noise is under this (noise-free simulations: float rounding,
                                       // 4e-5 mm, whose pattern reads 4-10)
};

struct NoiseCorrelation {
  double sigma_mm = 0.0;          // median residual sigma of the patches (0: none)
  double inflation = 1.0;  // 1 + density x the correlation summed over lags: Var(mean of N) / (sigma^2 / N), N >> 1
  std::vector<double> rho;        // correlation per lag bin ((k, k+1] resolutions), up to where it first falls to <= 0
  double bin_mm = 0.0;            // width of rho's lag bins (the resolution given)
  double density_per_mm2 = 0.0;   // median points per mm^2 of the patches
  std::size_t patches = 0;        // patches used
};

// Deterministic for any thread count. `resolution_mm` is the cloud's (spatial_resolution's median).
NoiseCorrelation estimate_noise_correlation(const KdTree& tree, double resolution_mm,
                                            const NoiseCorrelationParams& params = {});

// The variance of sum_i g_i e_i, e the points' noise (a fitted parameter's change, g its influence on it), over
// what independent noise gives: (sum_i g_i^2 + sum_{i != j} g_i g_j rho(|p_i - p_j|)) / sum_i g_i^2, at least 1.
// 1 when nc holds no correlation. Pairs found by a sweep along the points' longest extent.
double correlated_inflation(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& g,
                            const NoiseCorrelation& nc);

}  // namespace ewis
