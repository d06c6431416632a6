// How much neighbouring points' noise moves together (noise_correlation.hpp).
#include "ewis/filter/noise_correlation.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "ewis/core/parallel.hpp"
#include "ewis/core/robust.hpp"

namespace ewis {
namespace {

// Height fields over a patch's tangent plane: the polynomials of degree D in u and v, (D + 1)(D + 2) / 2 terms
// ordered by degree (1, u, v, u^2, uv, v^2, ...), u and v scaled to order 1.
template <int D>
constexpr int kHeightTerms = (D + 1) * (D + 2) / 2;
template <int D>
using HeightVec = Eigen::Matrix<double, kHeightTerms<D>, 1>;
template <int D>
using HeightMat = Eigen::Matrix<double, kHeightTerms<D>, kHeightTerms<D>>;

template <int D>
HeightVec<D> height_terms(double u, double v, double scale) {
  const double a = u * scale, b = v * scale;
  double pa[D + 1], pb[D + 1];
  pa[0] = pb[0] = 1.0;
  for (int i = 1; i <= D; ++i) {
    pa[i] = pa[i - 1] * a;
    pb[i] = pb[i - 1] * b;
  }
  HeightVec<D> t;
  int k = 0;
  for (int degree = 0; degree <= D; ++degree)
    for (int i = degree; i >= 0; --i) t[k++] = pa[i] * pb[degree - i];
  return t;
}

// The degree-D height field fitted by least squares to the points (u, v, h) where `use` is set; false when the
// normal equations are singular (a pivot under min_pivot_ratio x the largest).
template <int D>
bool fit_height_field(const std::vector<double>& u, const std::vector<double>& v, const std::vector<double>& h,
                      const std::vector<std::uint8_t>& use, double scale, double min_pivot_ratio, HeightVec<D>& coef,
                      Eigen::LDLT<HeightMat<D>>& ldlt) {
  HeightMat<D> a = HeightMat<D>::Zero();
  HeightVec<D> b = HeightVec<D>::Zero();
  for (std::size_t i = 0; i < u.size(); ++i) {
    if (!use[i]) continue;
    const HeightVec<D> t = height_terms<D>(u[i], v[i], scale);
    a.noalias() += t * t.transpose();
    b += t * h[i];
  }
  ldlt.compute(a);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > min_pivot_ratio * ldlt.vectorD().maxCoeff()))
    return false;
  coef = ldlt.solve(b);
  return coef.allFinite();
}

constexpr int kTerms = kHeightTerms<2>;  // the quadric: 1, u, v, u^2, uv, v^2
using Vec6 = HeightVec<2>;
using Mat6 = HeightMat<2>;

// One smooth patch's residuals off its quadric, in its tangent plane.
struct Patch {
  bool ok = false;
  double sigma_mm = 0.0;         // sqrt(sum r^2 / (n - 6))
  double density_per_mm2 = 0.0;  // all the cloud's points within half the patch radius, per mm^2
  std::vector<double> u, v, r;   // tangent coordinates (mm) and residuals (mm) of the points fitted
  std::vector<Vec6> x, y;        // each point's terms and (X^T X)^-1 times them: the hat value h_ij = x_i . y_j
};

// The residual sum of squares of a quartic height field over the points where `use` is set; -1 when singular.
double quartic_rss(const std::vector<double>& u, const std::vector<double>& v, const std::vector<double>& h,
                   const std::vector<std::uint8_t>& use, double scale) {
  HeightVec<4> coef;
  Eigen::LDLT<HeightMat<4>> ldlt;
  if (!fit_height_field<4>(u, v, h, use, scale, 1e-12, coef, ldlt)) return -1.0;
  double rss = 0.0;
  for (std::size_t i = 0; i < u.size(); ++i)
    if (use[i]) {
      const double r = h[i] - height_terms<4>(u[i], v[i], scale).dot(coef);
      rss += r * r;
    }
  return rss;
}

Patch measure_patch(const KdTree& tree, std::uint32_t seed, double radius_mm, const NoiseCorrelationParams& params,
                    std::vector<Neighbor>& nb) {
  Patch out;
  const std::vector<Eigen::Vector3f>& pts = tree.points();
  if (!pts[seed].allFinite()) return out;
  tree.radius_unsorted(pts[seed], float(radius_mm), nb);
  if (nb.size() < params.min_patch_points) return out;
  const double half2 = 0.25 * radius_mm * radius_mm;
  std::size_t inner = 0;
  for (const Neighbor& n : nb) inner += n.distance_sq <= half2;
  out.density_per_mm2 = double(inner) / (M_PI * half2);
  const std::vector<std::uint32_t> picked = evenly_strided(nb.size(), params.max_patch_points);
  const std::size_t m = picked.size();
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (std::uint32_t j : picked) c += pts[nb[j].index].cast<double>();
  c /= double(m);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::uint32_t j : picked) {
    const Eigen::Vector3d d = pts[nb[j].index].cast<double>() - c;
    cov.noalias() += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Eigen::Vector3d normal = eig.eigenvectors().col(0), e1 = eig.eigenvectors().col(2), e2 = normal.cross(e1);
  std::vector<double> u(m), v(m), h(m);
  for (std::size_t k = 0; k < m; ++k) {
    const Eigen::Vector3d d = pts[nb[picked[k]].index].cast<double>() - c;
    u[k] = d.dot(e1);
    v[k] = d.dot(e2);
    h[k] = d.dot(normal);
  }
  const double scale = 1.0 / radius_mm;  // terms of order 1
  std::vector<std::uint8_t> use(m, 1);
  Vec6 coef;
  Eigen::LDLT<Mat6> ldlt;
  std::vector<double> r(m), tmp;
  // Fitted, the residuals' outliers (beyond trim_sigmas robust sigmas) set aside, fitted again.
  for (int pass = 0; pass < 2; ++pass) {
    if (!fit_height_field<2>(u, v, h, use, scale, 1e-9, coef, ldlt)) return out;
    for (std::size_t k = 0; k < m; ++k) r[k] = h[k] - height_terms<2>(u[k], v[k], scale).dot(coef);
    if (pass == 1) break;
    const double s = robust_sigma(r, 1e-9, tmp);
    std::size_t kept = 0;
    for (std::size_t k = 0; k < m; ++k) kept += use[k] = std::abs(r[k]) <= params.trim_sigmas * s;
    if (kept < params.min_patch_points) return out;
  }
  // A surface curving within the patch (a cable, a small pipe) leaves the quadric's misfit, smooth, in the
  // residuals: such patches are left out.
  Eigen::Matrix2d hessian;
  hessian << 2.0 * coef[3], coef[4], coef[4], 2.0 * coef[5];
  hessian *= scale * scale;
  if (hessian.selfadjointView<Eigen::Lower>().eigenvalues().cwiseAbs().maxCoeff() * radius_mm >
      params.max_curvature_times_radius)
    return out;
  double sum2 = 0.0;
  std::size_t n = 0;
  for (std::size_t k = 0; k < m; ++k) {
    if (!use[k]) continue;
    out.u.push_back(u[k]);
    out.v.push_back(v[k]);
    out.r.push_back(r[k]);
    const Vec6 t = height_terms<2>(u[k], v[k], scale);
    out.x.push_back(t);
    out.y.push_back(ldlt.solve(t));
    sum2 += r[k] * r[k];
    ++n;
  }
  if (n <= std::size_t(kTerms) + 1) return out;
  out.sigma_mm = std::sqrt(sum2 / double(n - kTerms));
  // A shape the quadric misses (ridges, an edge's rounding) leaves smooth residuals a quartic takes up; noise,
  // smoothed over a few pixels or not, it hardly does.
  if (n > 16 + 1) {
    const double rss4 = quartic_rss(u, v, h, use, scale);
    if (!(rss4 >= 0.0) || rss4 / double(n - 15) < params.min_quartic_variance_ratio * out.sigma_mm * out.sigma_mm)
      return out;
  }
  out.ok = out.sigma_mm > 0.0;
  return out;
}

// Per lag bin: the observed semivariances over sigma^2, and what independent noise would give after the fit
// (1 - (h_ii + h_jj) / 2 + h_ij, from the hat matrix), summed over the patch's pairs.
struct LagSums {
  std::vector<double> observed, expected;
};

LagSums lag_sums(const Patch& p, double bin_mm, int bins) {
  LagSums s{std::vector<double>(bins, 0.0), std::vector<double>(bins, 0.0)};
  const double s2 = p.sigma_mm * p.sigma_mm, max_lag = bin_mm * bins;
  const std::size_t n = p.u.size();
  std::vector<double> hii(n);
  for (std::size_t i = 0; i < n; ++i) hii[i] = p.x[i].dot(p.y[i]);
  const double max_lag2 = max_lag * max_lag;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const double du = p.u[i] - p.u[j], dv = p.v[i] - p.v[j], d2 = du * du + dv * dv;
      if (!(d2 < max_lag2)) continue;
      const int k = std::min(bins - 1, int(std::sqrt(d2) / bin_mm));
      const double dr = p.r[i] - p.r[j];
      s.observed[k] += 0.5 * dr * dr / s2;
      s.expected[k] += 1.0 - 0.5 * (hii[i] + hii[j]) + p.x[i].dot(p.y[j]);
    }
  return s;
}

}  // namespace

NoiseCorrelation estimate_noise_correlation(const KdTree& tree, double resolution_mm,
                                            const NoiseCorrelationParams& params) {
  NoiseCorrelation out;
  if (!(resolution_mm > 0.0) || tree.size() < params.min_patch_points) return out;
  const double radius_mm = params.patch_radius * resolution_mm;
  const int bins = std::max(1, int(std::lround(params.max_lag)));
  // Evenly strided along the tree's leaf order: spread over the surfaces whatever the points' own order (a grid's
  // rows would put every seed of a stride of one row on its edge).
  const SpatialOrder order = tree.spatial_order();
  std::vector<std::uint32_t> seeds = evenly_strided(order.size(), params.patches);
  for (std::uint32_t& s : seeds) s = order[s];
  std::vector<Patch> patches(seeds.size());
  parallel_blocks(seeds.size(), 16, [&](std::size_t b, std::size_t e) {
    std::vector<Neighbor> nb;
    for (std::size_t i = b; i < e; ++i) patches[i] = measure_patch(tree, seeds[i], radius_mm, params, nb);
  });
  std::vector<double> sigmas;
  for (const Patch& p : patches)
    if (p.ok) sigmas.push_back(p.sigma_mm);
  if (sigmas.empty()) return out;
  const double median_sigma = median_in_place(sigmas);
  out.sigma_mm = median_sigma;
  if (!(median_sigma >= params.min_sigma_mm)) return out;
  std::vector<std::uint32_t> used;
  for (std::uint32_t i = 0; i < patches.size(); ++i)
    if (patches[i].ok && patches[i].sigma_mm <= params.max_patch_sigma_ratio * median_sigma) used.push_back(i);
  std::vector<LagSums> sums(used.size());
  parallel_blocks(used.size(), 8, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) sums[i] = lag_sums(patches[used[i]], resolution_mm, bins);
  });
  // Summed in patch order: the same bits for any thread count.
  std::vector<double> observed(bins, 0.0), expected(bins, 0.0);
  std::vector<double> density, sigma_used;
  for (std::size_t i = 0; i < used.size(); ++i) {
    for (int k = 0; k < bins; ++k) {
      observed[k] += sums[i].observed[k];
      expected[k] += sums[i].expected[k];
    }
    density.push_back(patches[used[i]].density_per_mm2);
    sigma_used.push_back(patches[used[i]].sigma_mm);
  }
  out.patches = used.size();
  if (out.patches < params.min_patches) return out;
  out.bin_mm = resolution_mm;
  out.sigma_mm = median_in_place(sigma_used);
  out.density_per_mm2 = median_in_place(density);
  // The correlation summed over a point's neighbours (density x annulus area per bin), up to where it first
  // falls to zero or below (beyond, the bins hold the estimate's own noise times ever larger areas).
  double sum = 0.0;
  for (int k = 0; k < bins; ++k) {
    if (!(expected[k] > 0.0)) break;
    const double rho = 1.0 - observed[k] / expected[k];
    if (!(rho > 0.0)) break;
    out.rho.push_back(rho);
    const double area = M_PI * resolution_mm * resolution_mm * double((k + 1) * (k + 1) - k * k);
    sum += rho * area * out.density_per_mm2;
  }
  out.inflation = 1.0 + sum;
  return out;
}

double correlated_inflation(const std::vector<Eigen::Vector3d>& points, const std::vector<double>& g,
                            const NoiseCorrelation& nc) {
  if (nc.rho.empty() || !(nc.bin_mm > 0.0) || points.size() < 2 || g.size() != points.size()) return 1.0;
  const double max_lag = nc.bin_mm * double(nc.rho.size()), max2 = max_lag * max_lag;
  const int bins = int(nc.rho.size());
  Eigen::Vector3d lo = points[0], hi = points[0];
  for (const Eigen::Vector3d& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  std::vector<std::uint32_t> order(points.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return points[a][axis] < points[b][axis] || (points[a][axis] == points[b][axis] && a < b);
  });
  double own = 0.0, cross = 0.0;
  for (std::size_t a = 0; a < order.size(); ++a) {
    const std::uint32_t i = order[a];
    own += g[i] * g[i];
    for (std::size_t b = a + 1; b < order.size(); ++b) {
      const std::uint32_t j = order[b];
      if (points[j][axis] - points[i][axis] >= max_lag) break;
      const double d2 = (points[j] - points[i]).squaredNorm();
      if (!(d2 < max2)) continue;
      cross += 2.0 * g[i] * g[j] * nc.rho[std::size_t(std::min(bins - 1, int(std::sqrt(d2) / nc.bin_mm)))];
    }
  }
  if (!(own > 0.0)) return 1.0;
  return std::max(1.0, (own + cross) / own);
}

}  // namespace ewis
