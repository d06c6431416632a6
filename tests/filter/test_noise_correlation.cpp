// The noise correlation estimate against surfaces whose noise is known: independent, and smoothed over a few
// grid cells as a stereo matcher's window smooths its depth errors.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ewis/filter/noise_correlation.hpp"
#include "ewis/filter/resolution.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis {
namespace {

constexpr int kSide = 300;           // grid cells a side
constexpr double kSpacingMm = 0.5;   // grid spacing

// Unit-variance noise on the grid, smoothed by a Gaussian of sigma_cells (separable, truncated at 4 sigma).
std::vector<double> smoothed_field(double sigma_cells, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<double> w(std::size_t(kSide) * kSide);
  for (double& x : w) x = g(rng);
  if (sigma_cells <= 0.0) return w;
  const int reach = int(std::ceil(4.0 * sigma_cells));
  std::vector<double> kernel(2 * reach + 1);
  for (int k = -reach; k <= reach; ++k) kernel[k + reach] = std::exp(-0.5 * k * k / (sigma_cells * sigma_cells));
  const auto blur = [&](const std::vector<double>& in, bool along_x) {
    std::vector<double> out(in.size(), 0.0);
    for (int j = 0; j < kSide; ++j)
      for (int i = 0; i < kSide; ++i) {
        double s = 0.0;
        for (int k = -reach; k <= reach; ++k) {
          const int a = along_x ? (i + k + kSide) % kSide : i, b = along_x ? j : (j + k + kSide) % kSide;
          s += kernel[k + reach] * in[std::size_t(b) * kSide + a];
        }
        out[std::size_t(j) * kSide + i] = s;
      }
    return out;
  };
  std::vector<double> f = blur(blur(w, true), false);
  double ss = 0.0;
  for (double x : f) ss += x * x;
  const double scale = 1.0 / std::sqrt(ss / double(f.size()));
  for (double& x : f) x *= scale;
  return f;
}

// The grid laid on a surface (height z(x, y)), displaced along z by independent noise of sigma_mm and the
// smoothed field times correlated_mm.
template <class Surface>
std::vector<Eigen::Vector3f> noisy_surface(const Surface& z, double sigma_mm, double correlated_mm,
                                           double sigma_cells) {
  const std::vector<double> field = smoothed_field(sigma_cells, 7);
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Eigen::Vector3f> pts;
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i) {
      const double x = i * kSpacingMm, y = j * kSpacingMm;
      const double dz = sigma_mm * g(rng) + correlated_mm * field[std::size_t(j) * kSide + i];
      pts.emplace_back(float(x), float(y), float(z(x, y) + dz));
    }
  return pts;
}

NoiseCorrelation estimate(const std::vector<Eigen::Vector3f>& pts) {
  const KdTree tree(pts);
  return estimate_noise_correlation(tree, spatial_resolution(tree).median_mm);
}

const auto kFlat = [](double, double) { return 0.0; };

TEST(NoiseCorrelation, IndependentNoiseReadsOne) {
  const NoiseCorrelation nc = estimate(noisy_surface(kFlat, 0.1, 0.0, 0.0));
  EXPECT_GT(nc.patches, 80u);
  EXPECT_NEAR(nc.sigma_mm, 0.1, 0.01);
  EXPECT_LT(nc.inflation, 1.3);
}

TEST(NoiseCorrelation, AGentleCurveIsNoCorrelation) {
  // A cylinder of 40 mm radius (the grid's x across it) with little noise: a quadric over a 12 mm patch misfits it
  // by up to 0.04 mm, about the noise (0.05 mm); that must stay well under the inflation the fits count (3).
  const auto cylinder = [](double x, double) {
    const double u = x - 75.0;
    return std::sqrt(std::max(0.0, 1600.0 - u * u));
  };
  const NoiseCorrelation nc = estimate(noisy_surface(cylinder, 0.05, 0.0, 0.0));
  EXPECT_GT(nc.patches, 40u);
  EXPECT_LT(nc.inflation, 2.0);
}

TEST(NoiseCorrelation, TightlyCurvedSurfacesAreNoCorrelation) {
  // Ridges 3 mm high every 25 mm (curving down to 5.3 mm radius, as cables and small pipes do) with little
  // independent noise: a quadric over a 12 mm patch misfits them smoothly; such patches are left out.
  const auto ridges = [](double x, double) { return 3.0 * std::sin(x / 4.0); };
  const NoiseCorrelation nc = estimate(noisy_surface(ridges, 0.05, 0.0, 0.0));
  EXPECT_LT(nc.inflation, 1.5);
}

TEST(NoiseCorrelation, NoiseSmoothedOverAFewPointsInflatesTheVariance) {
  // 0.2 mm smoothed over a Gaussian of 2 cells plus 0.05 mm independent: a mean over many points varies like one
  // over 1 + 0.94 x (4 pi 2^2 - 1) = 47 times fewer independent points. The patches' quadrics take up some of the
  // smooth part (the estimate is low by up to a third), and the estimate must not confuse it with independent noise.
  const double correlated = 0.2, independent = 0.05, sigma_cells = 2.0;
  const double share = correlated * correlated / (correlated * correlated + independent * independent);
  const double truth = 1.0 + share * (4.0 * M_PI * sigma_cells * sigma_cells - 1.0);
  const NoiseCorrelation nc = estimate(noisy_surface(kFlat, independent, correlated, sigma_cells));
  EXPECT_GT(nc.patches, 80u);
  EXPECT_GT(nc.inflation, 0.5 * truth);
  EXPECT_LT(nc.inflation, 1.2 * truth);
  ASSERT_FALSE(nc.rho.empty());
  EXPECT_GT(nc.rho.front(), 0.5);
}

TEST(NoiseCorrelation, AnInfluenceOfOneSignIsInflatedAsAMeanAndOneOfBothSignsLess) {
  const NoiseCorrelation nc = estimate(noisy_surface(kFlat, 0.05, 0.2, 2.0));
  ASSERT_GT(nc.inflation, 10.0);
  // A 20 x 20 mm square of the grid, its points as doubles.
  std::vector<Eigen::Vector3d> pts;
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; ++i) pts.emplace_back(i * kSpacingMm, j * kSpacingMm, 0.0);
  const std::vector<double> mean(pts.size(), 1.0);
  const double of_mean = correlated_inflation(pts, mean, nc);
  EXPECT_GT(of_mean, 0.6 * nc.inflation);  // the square's edges have fewer neighbours than the plane's points
  EXPECT_LT(of_mean, 1.05 * nc.inflation);
  // Signs alternating every 1.5 mm along x: neighbours' errors cancel in the sum.
  std::vector<double> wavy(pts.size());
  for (std::size_t k = 0; k < pts.size(); ++k) wavy[k] = (int(pts[k].x() / 1.5) % 2) ? 1.0 : -1.0;
  const double of_wavy = correlated_inflation(pts, wavy, nc);
  EXPECT_GE(of_wavy, 1.0);
  EXPECT_LT(of_wavy, 0.5 * of_mean);
  // Without correlation: 1.
  EXPECT_EQ(correlated_inflation(pts, mean, NoiseCorrelation{}), 1.0);
}

TEST(NoiseCorrelation, TooFewPointsReadOne) {
  const std::vector<Eigen::Vector3f> pts = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const KdTree tree(pts);
  const NoiseCorrelation nc = estimate_noise_correlation(tree, 1.0);
  EXPECT_EQ(nc.patches, 0u);
  EXPECT_EQ(nc.inflation, 1.0);
}

}  // namespace
}  // namespace ewis
