// paper 4.3.1, measured in 3D: local circle fits along the measured centreline (see bend_radius.hpp).
#include "ewis/inspect/bend_radius.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "ewis/core/parallel.hpp"
#include "ewis/inspect/circle_fit.hpp"

namespace ewis {
namespace {

// How a stretch [a, b) of samples departs from a circle fitted without it (a prediction, so the fit cannot
// bend to absorb it): the mean signed in-plane residual (a straight run beyond a bend lies outside the
// circle, t^2 / 2R at t past the junction) and the RMS of the full 3D residual.
struct Departure {
  double mean_radial = 0.0;
  double rms = 0.0;
};
Departure departure(const Circle3d& c, const std::vector<Eigen::Vector3d>& s, std::size_t a, std::size_t b) {
  Departure d;
  if (b <= a) return d;
  double sum_r = 0, sum2 = 0;
  for (std::size_t i = a; i < b; ++i) {
    double radial = 0;
    const double e = circle_distance(c, s[i], &radial);
    sum_r += radial;
    sum2 += e * e;
  }
  d.mean_radial = sum_r / double(b - a);
  d.rms = std::sqrt(sum2 / double(b - a));
  return d;
}

Circle3d fit_range(const std::vector<Eigen::Vector3d>& s, std::size_t a, std::size_t b_inclusive) {
  return fit_circle_3d(s.data() + a, b_inclusive - a + 1);
}

// Uniform arc-length resampling of a polyline (first and last points kept).
std::vector<Eigen::Vector3d> resample(const std::vector<Eigen::Vector3d>& pts, const std::vector<double>& arc,
                                      double step) {
  std::vector<Eigen::Vector3d> out;
  const double total = arc.back();
  const std::size_t count = static_cast<std::size_t>(std::floor(total / step)) + 1;
  out.reserve(count + 1);
  std::size_t seg = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const double s = double(i) * step;
    while (seg + 2 < arc.size() && arc[seg + 1] < s) ++seg;
    const double len = arc[seg + 1] - arc[seg];
    const double t = len > 0 ? std::clamp((s - arc[seg]) / len, 0.0, 1.0) : 0.0;
    out.push_back(pts[seg] + t * (pts[seg + 1] - pts[seg]));
  }
  if (total - double(count - 1) * step > 1e-6 * step) out.push_back(pts.back());
  return out;
}

double sagitta(double radius, double arc_len) {
  const double half_angle = std::min(arc_len / (2.0 * radius), M_PI / 2);
  return radius * (1.0 - std::cos(half_angle));
}

}  // namespace

BendRadiusResult measure_bend_radius(const std::vector<Eigen::Vector3d>& centerline, double diameter_mm,
                                     const BendRadiusParams& params) {
  BendRadiusResult result;
  std::vector<Eigen::Vector3d> pts;
  pts.reserve(centerline.size());
  for (const auto& p : centerline) {
    if (!p.allFinite()) continue;
    if (!pts.empty() && (p - pts.back()).norm() < 1e-9) continue;
    pts.push_back(p);
  }
  if (pts.size() < 2 || !(diameter_mm > 0)) return result;
  std::vector<double> arc(pts.size(), 0.0);
  for (std::size_t i = 1; i < pts.size(); ++i) arc[i] = arc[i - 1] + (pts[i] - pts[i - 1]).norm();
  result.length_mm = arc.back();
  if (pts.size() < 3) return result;

  // Bound the work on absurdly long inputs: at most ~20000 samples.
  const double step = std::max(params.sample_step_diameters * diameter_mm, result.length_mm / 20000.0);
  const std::vector<Eigen::Vector3d> s = resample(pts, arc, step);
  const std::size_t m = s.size();
  if (m < 5) return result;
  const std::size_t k0 = std::max<std::size_t>(2, std::lround(std::max(params.min_half_window_diameters * diameter_mm, params.min_half_window_mm) / step));
  const std::size_t cstep = std::max<std::size_t>(1, std::lround(params.centre_step_diameters * diameter_mm / step));
  std::vector<std::size_t> centres;
  for (std::size_t c = 0; c < m; c += cstep) centres.push_back(c);
  if (centres.back() != m - 1) centres.push_back(m - 1);

  // The smallest window around each centre (shifted inside the curve at the ends).
  auto min_window = [&](std::size_t c, std::size_t& a, std::size_t& b) {
    const std::size_t span = std::min(2 * k0, m - 1);
    a = c >= k0 ? c - k0 : 0;
    if (a + span > m - 1) a = m - 1 - span;
    b = a + span;
  };
  std::vector<double> base_rms(centres.size(), 0.0);
  parallel_for_each_index(centres.size(), [&](std::size_t i) {
    std::size_t a, b;
    min_window(centres[i], a, b);
    const Circle3d c = fit_range(s, a, b);
    base_rms[i] = c.ok ? c.rms_mm : std::numeric_limits<double>::infinity();
  }, 4);
  // Centreline noise: the median residual of the smallest windows (a smooth curve is locally a circle, so
  // what is left is noise; junction windows are a minority and the median ignores them).
  std::vector<double> sorted = base_rms;
  std::sort(sorted.begin(), sorted.end());
  double noise = sorted[sorted.size() / 2];
  if (!std::isfinite(noise)) noise = 0.0;
  noise = std::max(noise, params.min_noise_mm);
  result.noise_mm = noise;
  const double total_limit = params.grow_total_factor * noise;
  const double ext_limit = params.grow_extension_factor * noise;
  const double max_radius = params.straight_limit_diameters * diameter_mm;

  // Samples per independent input point (resampling interpolates; it adds no information).
  const double input_spacing = result.length_mm / double(pts.size() - 1);
  const double samples_per_point = std::max(1.0, input_spacing / step);
  const double sigma_radial = noise / std::sqrt(2.0);  // in-plane share of an isotropic 3D noise

  struct Fit {
    Circle3d circle;
    std::size_t a = 0, b = 0;
    bool bend = false;
  };
  std::vector<Fit> fits(centres.size());
  parallel_for_each_index(centres.size(), [&](std::size_t i) {
    Fit& f = fits[i];
    min_window(centres[i], f.a, f.b);
    f.circle = fit_range(s, f.a, f.b);
    if (f.circle.ok && !f.circle.straight && double(f.b - f.a) * step > params.short_window_turn_rad * f.circle.radius_mm) {
      const std::size_t c = centres[i];
      const std::size_t k1 = std::max<std::size_t>(
          {2, k0 / 2, static_cast<std::size_t>(std::lround(params.short_half_window_diameters * diameter_mm / step))});
      if (k1 < k0) {
        std::size_t a = c >= k1 ? c - k1 : 0;
        if (a + 2 * k1 > m - 1) a = m - 1 - std::min(2 * k1, m - 1);
        const std::size_t b = std::min(m - 1, a + 2 * k1);
        const Circle3d sc = fit_range(s, a, b);
        if (sc.ok && !sc.straight && sc.rms_mm <= total_limit) {
          f.circle = sc;
          f.a = a;
          f.b = b;
        }
      }
    }
    // Accepts the stretch [x, y) as part of the circle `c` fitted on `m` samples: no systematic departure
    // (3 sigma of the mean of the stretch's and the fit's noise) and no excess scatter.
    auto fits_circle = [&](const Circle3d& c, std::size_t m, std::size_t x, std::size_t y) {
      const Departure d = departure(c, s, x, y);
      const double k_eff = std::max(1.0, double(y - x) / samples_per_point);
      const double m_eff = std::max(1.0, double(m) / samples_per_point);
      // 4 / m: a circle extrapolated past its window's end is less certain than at its middle.
      const double mean_limit = 3.0 * sigma_radial * std::sqrt(1.0 / k_eff + 4.0 / m_eff);
      // the scatter of k points: rms below noise x (1 + 3 / sqrt(k)) (a loose chi-square bound)
      return std::abs(d.mean_radial) <= mean_limit && d.rms <= ext_limit * (1.0 + 3.0 / std::sqrt(k_eff));
    };
    const auto is_bend = [&](const Circle3d& c, std::size_t a, std::size_t b) {
      return c.ok && !c.straight && c.radius_mm <= max_radius &&
             sagitta(c.radius_mm, double(b - a) * step) >= params.sagitta_noise_factor * noise;
    };
    if (f.circle.ok && f.circle.rms_mm <= total_limit) {
      // Grow each side while the curve stays this circle (bounded: each accepted step adds >= 1 sample).
      // A side whose growth was refused gives back its last accepted step: the junction (bend to straight,
      // bend to bend) lies in that step or the refused one, and keeping it would bias the radius high.
      std::size_t last_left = 0, last_right = 0;
      bool left_open = f.a > 0, right_open = f.b < m - 1;
      bool left_refused = false, right_refused = false;
      for (int it = 0; it < 4096 && (left_open || right_open); ++it) {
        // A straight stretch needs no precise radius: stop once it is twice the smallest window.
        if (f.b - f.a >= 4 * k0 && !is_bend(f.circle, f.a, f.b)) break;
        const std::size_t delta = std::max<std::size_t>(1, std::lround(params.grow_fraction * double(f.b - f.a)));
        if (left_open) {
          const std::size_t na = f.a > delta ? f.a - delta : 0;
          const Circle3d c = fit_range(s, na, f.b);
          if (c.ok && fits_circle(c, f.b - na + 1, na, f.a) && c.rms_mm <= total_limit) {
            f.circle = c;
            last_left = f.a - na;
            f.a = na;
            left_open = f.a > 0;
          } else {
            left_open = false;
            left_refused = true;
          }
        }
        if (right_open) {
          const std::size_t nb = std::min(m - 1, f.b + delta);
          const Circle3d c = fit_range(s, f.a, nb);
          if (c.ok && fits_circle(c, nb - f.a + 1, f.b + 1, nb + 1) && c.rms_mm <= total_limit) {
            f.circle = c;
            last_right = nb - f.b;
            f.b = nb;
            right_open = f.b < m - 1;
          } else {
            right_open = false;
            right_refused = true;
          }
        }
      }
      const std::size_t min_span = std::min(2 * k0, m - 1);
      std::size_t a = f.a + (left_refused ? last_left : 0), b = f.b - (right_refused ? last_right : 0);
      if ((a != f.a || b != f.b) && b > a && b - a >= min_span) {
        const Circle3d c = fit_range(s, a, b);
        if (c.ok) {
          f.circle = c;
          f.a = a;
          f.b = b;
        }
      }
    }
    f.bend = is_bend(f.circle, f.a, f.b);
  }, 1);

  result.profile.resize(centres.size());
  int best = -1;
  for (std::size_t i = 0; i < centres.size(); ++i) {
    BendSample& p = result.profile[i];
    p.arc_mm = double(centres[i]) * step;
    p.point = s[centres[i]];
    p.window_start_mm = double(fits[i].a) * step;
    p.window_end_mm = double(fits[i].b) * step;
    if (fits[i].bend) {
      p.radius_mm = fits[i].circle.radius_mm;
      // resampling multiplies the points, not the information
      p.radius_se_mm = fits[i].circle.radius_se_mm * std::sqrt(samples_per_point);
      const auto score = [&](const BendSample& q) { return q.radius_mm + params.selection_se_factor * q.radius_se_mm; };
      if (best < 0 || score(p) < score(result.profile[best])) best = int(i);
    }
  }
  if (best >= 0) {
    const Fit& f = fits[best];
    result.min_radius_mm = f.circle.radius_mm;
    result.min_radius_se_mm = result.profile[best].radius_se_mm;
    const std::size_t mid = (f.a + f.b) / 2;
    result.location = s[mid];
    result.location_arc_mm = double(mid) * step;
    result.circle_center = f.circle.center;
    result.circle_normal = f.circle.normal;
  }
  return result;
}

PaperBendResult paper_bend_radius(const std::vector<Cylinder>& chain, const Eigen::Vector3d& optical_axis,
                                  double diameter_mm, const PaperBendParams& params) {
  PaperBendResult out;
  std::vector<Eigen::Vector3d> pts;
  for (const auto& c : chain) {
    for (const Eigen::Vector3d& p : {c.start, c.end}) {
      if (!p.allFinite()) continue;
      if (!pts.empty() && (p - pts.back()).norm() < 1e-6) continue;
      pts.push_back(p);
    }
  }
  out.points = pts.size();
  if (pts.size() < 3 || !(optical_axis.norm() > 0)) return out;
  // paper 4.3.1: projection on the plane perpendicular to the camera's optical axis.
  const Eigen::Vector3d z = optical_axis.normalized();
  const Eigen::Vector3d u = z.unitOrthogonal();
  const Eigen::Vector3d v = z.cross(u);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : pts) mean += p;
  mean /= double(pts.size());
  std::vector<Eigen::Vector2d> q;
  q.reserve(pts.size());
  for (const auto& p : pts) q.emplace_back((p - mean).dot(u), (p - mean).dot(v));
  RansacCircleParams rp;
  rp.inlier_mm = params.inlier_mm > 0 ? params.inlier_mm : std::max(0.5, 0.05 * diameter_mm);
  rp.iterations = params.iterations;
  rp.min_radius_mm = 0.5 * diameter_mm;
  rp.max_radius_mm = params.max_radius_diameters * diameter_mm;
  rp.seed = params.seed;
  const RansacCircleResult r = ransac_circle_2d(q, rp);
  out.inliers = r.inliers.size();
  if (!r.circle.ok || r.circle.radius_mm > rp.max_radius_mm) return out;
  out.radius_mm = r.circle.radius_mm;
  out.center = mean + r.circle.center.x() * u + r.circle.center.y() * v;
  return out;
}

}  // namespace ewis
