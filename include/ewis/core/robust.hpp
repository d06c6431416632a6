#pragma once
// Robust statistics shared by the fits (ICP, cylinders, fillets, smooth tubes): the Cauchy kernel and the robust
// sigma (1.4826 x the median absolute deviation, the normal distribution's sigma for Gaussian residuals).
#include <algorithm>
#include <cmath>
#include <vector>

namespace ewis {

// Cauchy kernel of scale c: rho(r) = c^2/2 log(1 + (r/c)^2), IRLS weight rho'(r)/r = 1 / (1 + (r/c)^2).
inline double cauchy_rho(double r, double c) { return 0.5 * c * c * std::log1p((r / c) * (r / c)); }
inline double cauchy_weight(double r, double c) { return 1.0 / (1.0 + (r / c) * (r / c)); }

// The median of v (the upper one for an even count; 0 when empty). Reorders v.
inline double median_in_place(std::vector<double>& v) {
  if (v.empty()) return 0.0;
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  return v[mid];
}

// The median of r and its robust sigma, at least floor; tmp is a reusable buffer (no allocation per call).
inline void median_and_robust_sigma(const std::vector<double>& r, double floor, std::vector<double>& tmp,
                                    double& median, double& sigma) {
  tmp.assign(r.begin(), r.end());
  median = median_in_place(tmp);
  for (double& x : tmp) x = std::abs(x - median);
  sigma = std::max(1.4826 * median_in_place(tmp), floor);
}

inline double robust_sigma(const std::vector<double>& r, double floor, std::vector<double>& tmp) {
  double median = 0.0, sigma = 0.0;
  median_and_robust_sigma(r, floor, tmp, median, sigma);
  return sigma;
}

inline double robust_sigma(const std::vector<double>& r, double floor) {
  std::vector<double> tmp;
  return robust_sigma(r, floor, tmp);
}

}  // namespace ewis
