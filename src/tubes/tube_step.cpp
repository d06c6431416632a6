// paper 4.2.2-4.2.4: the search structure moved along the tube, one sub-cable per step.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "ewis/filter/normals.hpp"
#include "ewis/tubes/directions.hpp"
#include "tube_internal.hpp"

namespace ewis::tubes_detail {

CylinderFitParams Context::fit_params(double radius_mm, const Eigen::Vector3d& origin) const {
  CylinderFitParams fp;
  fp.min_sigma_mm = std::max(0.02, 0.05 * resolution_mm);
  fp.max_radius_mm = 3.0 * radius_mm;
  fp.fix_radius = thin;
  fp.use_sensor = params.has_sensor;
  fp.sensor = params.sensor_position - origin;
  return fp;
}

void gather(Context& ctx, const Eigen::Vector3d& center, double radius, const Eigen::Vector3d& origin,
            std::vector<Eigen::Vector3d>& rel, std::vector<std::uint32_t>* ids) {
  rel.clear();
  if (ids) ids->clear();
  // the tree's visiting order is deterministic (it depends on the cloud only), so no sort is needed: sorting
  // the ~10^3-10^4 points of every step's ball cost a fifth of the trace time
  ctx.tree.radius_unsorted(center.cast<float>(), static_cast<float>(radius), ctx.scratch);
  rel.reserve(ctx.scratch.size());
  if (ids) ids->reserve(ctx.scratch.size());
  for (const Neighbor& nb : ctx.scratch) {
    if (!ctx.usable(nb.index)) continue;
    rel.push_back(ctx.cloud.points[nb.index].cast<double>() - origin);
    if (ids) ids->push_back(nb.index);
  }
}

bool behind_tube(const Eigen::Vector3d& sensor, const Eigen::Vector3d& q, const Eigen::Vector3d& axis_point,
                 const Eigen::Vector3d& axis, double radius_mm, double margin_mm, double t0, double t1) {
  const Eigen::Vector3d ray = q - sensor;
  const double len = ray.norm();
  if (len <= 0) return false;
  const Eigen::Vector3d e = ray / len;
  const Eigen::Vector3d s0 = sensor - axis_point;
  const Eigen::Vector3d sp = s0 - axis * axis.dot(s0), ep = e - axis * axis.dot(e);
  const double ee = ep.squaredNorm();
  if (ee < 1e-12) return false;  // the ray runs along the axis
  const double t = -sp.dot(ep) / ee;  // along the ray, where it passes closest to the axis line
  if (t <= 0 || t + margin_mm >= len) return false;
  const Eigen::Vector3d c = s0 + e * t;
  if ((c - axis * axis.dot(c)).squaredNorm() >= radius_mm * radius_mm) return false;
  const double along = axis.dot(c) + axis.dot(axis_point);  // in the frame of `q` (the window's bounds)
  return along >= t0 && along <= t1;
}

bool front_clear(Context& ctx, const Eigen::Vector3d& origin, const Eigen::Vector3d& axis_point,
                 const Eigen::Vector3d& axis, double radius_mm) {
  if (!ctx.params.has_sensor) return true;
  const Eigen::Vector3d sensor = ctx.params.sensor_position - origin;
  const Eigen::Vector3d to_sensor = sensor - axis_point;
  Eigen::Vector3d n = to_sensor - axis * axis.dot(to_sensor);
  if (n.squaredNorm() < 1e-12) return true;  // looking along the axis
  n.normalize();
  const Eigen::Vector3d front = axis_point + n * radius_mm;  // the tube's point nearest the sensor, about
  const Eigen::Vector3d ray = sensor - front;
  const double len = ray.norm();
  if (len <= 0) return true;
  const Eigen::Vector3d e = ray / len;
  const double rq = std::max(ctx.resolution_mm, 0.25 * radius_mm);
  const double reach = std::min(len, std::max(10.0 * radius_mm, 30.0));
  for (double t = ctx.tolerance_mm + 1.5 * rq; t <= reach; t += 1.5 * rq) {
    const Eigen::Vector3d c = origin + front + e * t;
    ctx.tree.radius_unsorted(c.cast<float>(), static_cast<float>(rq), ctx.scratch);
    if (ctx.scratch.size() >= 3) return false;  // every point hides what lies behind it (see the declaration)
  }
  return true;
}

HiddenPoints drop_hidden_by_tube(Context& ctx, std::vector<Eigen::Vector3d>& rel, std::vector<std::uint32_t>& ids,
                                 const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double radius_mm,
                                 double t0, double t1) {
  if (!ctx.params.has_sensor || !ctx.params.hidden_check || rel.size() != ids.size()) return HiddenPoints::Kept;
  const Eigen::Vector3d sensor = ctx.params.sensor_position - origin;
  std::vector<char> hidden(rel.size(), 0);
  std::size_t n_hidden = 0;
  for (std::size_t k = 0; k < rel.size(); ++k) {
    hidden[k] = behind_tube(sensor, rel[k], Eigen::Vector3d::Zero(), dir, radius_mm, ctx.tolerance_mm, t0, t1);
    n_hidden += hidden[k];
  }
  if (n_hidden == 0) return HiddenPoints::None;
  // Only a tube the sensor sees hides anything: one traced in the shadow of another surface (a "tube" of mixed
  // points hanging under a cable) is hidden itself, and its own points are no evidence.
  if (!front_clear(ctx, origin, dir * (0.5 * (t0 + t1)), dir, radius_mm)) return HiddenPoints::Kept;
  std::size_t w = 0;
  for (std::size_t k = 0; k < rel.size(); ++k) {
    if (hidden[k]) continue;
    rel[w] = rel[k];
    ids[w] = ids[k];
    ++w;
  }
  rel.resize(w);
  ids.resize(w);
  return HiddenPoints::Dropped;
}

void drop_facing_away(Context& ctx, std::vector<Eigen::Vector3d>& win, std::vector<std::uint32_t>& ids,
                      const Eigen::Vector3d& axis) {
  if (!ctx.params.has_sensor || !ctx.params.facing_check || win.size() != ids.size() || win.empty()) return;
  std::vector<std::uint32_t> missing;
  for (std::uint32_t i : ids)
    if (!ctx.normals.count(i)) missing.push_back(i);
  if (!missing.empty()) {
    NormalParams np;
    np.k = 12;
    np.viewpoint = ctx.params.sensor_position.cast<float>();
    const std::vector<Eigen::Vector3f> n = estimate_normals(ctx.tree, missing, np);
    for (std::size_t k = 0; k < missing.size(); ++k) ctx.normals.emplace(missing[k], n[k]);
  }
  std::vector<char> keep(win.size(), 1);
  std::size_t kept = 0;
  for (std::size_t k = 0; k < win.size(); ++k) {
    const Eigen::Vector3d radial = win[k] - axis * axis.dot(win[k]);
    const Eigen::Vector3f& n = ctx.normals.at(ids[k]);
    const double len = radial.norm();
    // an undefined normal (0, 0, 0) or a point on the axis: no evidence either way
    if (len > 0 && n.squaredNorm() > 0 && n.cast<double>().dot(radial) < ctx.params.facing_min_cos * len) keep[k] = 0;
    kept += keep[k];
  }
  if (kept == win.size() || 2 * kept < win.size()) return;
  std::size_t w = 0;
  for (std::size_t k = 0; k < win.size(); ++k)
    if (keep[k]) {
      win[w] = win[k];
      ids[w] = ids[k];
      ++w;
    }
  win.resize(w);
  ids.resize(w);
}

namespace {

// The local points as float arrays (x, y, z, squared norm): the counting loop below is the hot spot.
struct Local {
  std::vector<float> x, y, z, n2;
};

Local make_local(const std::vector<Eigen::Vector3d>& rel, std::size_t stride) {
  Local l;
  const std::size_t n = (rel.size() + stride - 1) / stride;
  l.x.reserve(n);
  l.y.reserve(n);
  l.z.reserve(n);
  l.n2.reserve(n);
  for (std::size_t i = 0; i < rel.size(); i += stride) {
    l.x.push_back(static_cast<float>(rel[i].x()));
    l.y.push_back(static_cast<float>(rel[i].y()));
    l.z.push_back(static_cast<float>(rel[i].z()));
    l.n2.push_back(static_cast<float>(rel[i].squaredNorm()));
  }
  return l;
}

// Shell count of one candidate axis u through the origin.
int shell_count(const Local& l, const Eigen::Vector3d& u, float lo2, float hi2, float t0, float t1) {
  const float ux = static_cast<float>(u.x()), uy = static_cast<float>(u.y()), uz = static_cast<float>(u.z());
  int count = 0;
  const std::size_t n = l.x.size();
  for (std::size_t i = 0; i < n; ++i) {
    const float t = l.x[i] * ux + l.y[i] * uy + l.z[i] * uz;
    const float d2 = l.n2[i] - t * t;
    count += (t >= t0) & (t <= t1) & (d2 >= lo2) & (d2 <= hi2);
  }
  return count;
}

Eigen::Vector3d best_in(const Local& l, const Eigen::Vector3d& around, const std::vector<Eigen::Vector3d>& dirs,
                        float lo2, float hi2, float t0, float t1, int& best) {
  const Eigen::Matrix3d rot = rotation_from_z(around);
  Eigen::Vector3d best_u = around.normalized();
  best = -1;
  for (const Eigen::Vector3d& dz : dirs) {
    const Eigen::Vector3d u = rot * dz;
    const int c = shell_count(l, u, lo2, hi2, t0, t1);
    if (c > best) {  // strict: ties keep the earlier candidate (the continuation comes first)
      best = c;
      best_u = u;
    }
  }
  return best_u;
}

// paper 4.2.3 (height): where the surface ends along `axis` from `origin`: the farthest shell point with a
// dense stretch of surface (>= need points within w) just behind it. Outliers, even flying-pixel clusters
// near the silhouette, are never that dense, so they cannot stretch the tube.
double dense_end(const std::vector<Eigen::Vector3d>& rel, const Eigen::Vector3d& origin, const Eigen::Vector3d& axis,
                 double r, double tol, double t_max, double w, double need) {
  const double lo = std::max(0.0, r - tol), hi = r + tol;
  std::vector<double> ts;
  for (const Eigen::Vector3d& q0 : rel) {
    const Eigen::Vector3d q = q0 - origin;
    const double t = q.dot(axis);
    if (t < 0 || t > t_max) continue;
    const double d2 = q.squaredNorm() - t * t;
    if (d2 >= lo * lo && d2 <= hi * hi) ts.push_back(t);
  }
  std::sort(ts.begin(), ts.end());
  std::size_t lo_i = ts.size();
  for (std::size_t j = ts.size(); j-- > 0;) {
    if (lo_i > j) lo_i = j;
    while (lo_i > 0 && ts[lo_i - 1] >= ts[j] - w) --lo_i;
    if (static_cast<double>(j - lo_i + 1) >= need) return ts[j];
  }
  return 0.0;
}

}  // namespace

Eigen::Vector3d search_direction(const Context& ctx, const std::vector<Eigen::Vector3d>& rel,
                                 const Eigen::Vector3d& around, const std::vector<Eigen::Vector3d>& dirs, double r,
                                 double tol, double t0, double t1, int& best_count) {
  const double lo = std::max(0.0, r - tol), hi = r + tol;
  // bound the work on dense data: a deterministic stride keeps at most ~1000 points per count
  const std::size_t stride = std::max<std::size_t>(1, rel.size() / 1000);
  const Local l = make_local(rel, stride);
  const float lo2 = static_cast<float>(lo * lo), hi2 = static_cast<float>(hi * hi);
  const float f0 = static_cast<float>(t0), f1 = static_cast<float>(t1);
  int c0 = 0, c1 = 0;
  Eigen::Vector3d u = best_in(l, around, dirs, lo2, hi2, f0, f1, c0);
  u = best_in(l, u, ctx.fine1, lo2, hi2, f0, f1, c1);
  u = best_in(l, u, ctx.fine2, lo2, hi2, f0, f1, best_count);
  best_count *= static_cast<int>(stride);
  return u.normalized();
}

double local_resolution(const KdTree& tree, const Eigen::Vector3d& p) {
  std::vector<Neighbor> nb, nb2;
  tree.knn(p.cast<float>(), 48, nb);
  std::vector<double> d;
  for (const Neighbor& n : nb) {
    tree.knn(tree.points()[n.index], 2, nb2);
    if (nb2.size() == 2) d.push_back(std::sqrt(nb2[1].distance_sq));
  }
  if (d.empty()) return 1.0;
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return std::max(d[d.size() / 2], 1e-3);
}

// A radius change beyond the limit must cost the fit held at the old radius more than this (chi-square with
// one degree of freedom, in units of the fit's own noise: 4 standard errors) to end the tube.
constexpr double kRadiusChangeChi2 = 16.0;

// A thin tube's step whose axis lies within 25 deg of the sensor's ray ends the tube (see propagate_step).
const double kThinAlongRayCos = std::cos(25.0 * M_PI / 180.0);
constexpr double kThinBinPoints = 8.0;  // expected points per bin of a thin tube's histogram (see propagate_step)

StepResult propagate_step(Context& ctx, const Eigen::Vector3d& a, const Eigen::Vector3d& d_in, double r_ref,
                          double arc_ref_deg, double rms_ref_mm, bool bridging, double scale) {
  StepResult st;
  st.start = a;
  const Eigen::Vector3d d = d_in.normalized();
  const double L = ctx.step_mm * scale, tol = ctx.tolerance_mm;
  const double h = std::max(ctx.half_window_mm * scale, 2.0 * ctx.resolution_mm);
  const double reach = L + h;
  std::vector<Eigen::Vector3d> rel;
  std::vector<std::uint32_t> rel_ids;
  // one k-d tree query per step (paper 4.2.2 "fast"); the counting below works on this local set
  gather(ctx, a + d * (0.5 * reach), std::sqrt(0.25 * reach * reach + (r_ref + 2 * tol) * (r_ref + 2 * tol)) + reach * 0.5, a,
         rel, &rel_ids);
  // points the tube (as it runs so far) hides from the sensor: mixed pixels hanging from its silhouette
  const HiddenPoints hidden = drop_hidden_by_tube(ctx, rel, rel_ids, a, d, r_ref, -h, reach);
  if (rel.size() < 6) {
    st.fail = "no data";
    return st;
  }
  // paper 4.2.2: the fullest candidate cylinder starting at a (within the search cone)
  int score = 0;
  const std::vector<Eigen::Vector3d>& cone = bridging ? ctx.bridge : ctx.coarse;
  const Eigen::Vector3d u = search_direction(ctx, rel, d, cone, r_ref, tol, 0.0, reach, score);
  const double expected_per_mm = std::max(ctx.expected_density, 1e-6);
  if (score < std::max(6.0, 0.2 * expected_per_mm * L)) {
    st.fail = "no data";
    return st;
  }
  // paper 4.2.3 / Fig. 10: height from the histogram of the projections on the axis: stop where bins empty
  // A thin tube's bins are long enough to expect kThinBinPoints each: a 1.9 mm wire at 0.63 mm pixels shows ~3 points
  // per mm, a 1.5-resolution bin ~3, and one bin in five held fewer than the 2 that end the tube (Poisson).
  const double thin_bw = ctx.thin ? std::min(kThinBinPoints / expected_per_mm, reach) : 0.0;
  const double bw = std::max({1.5 * ctx.resolution_mm, reach / 12.0, thin_bw});
  const int nbins = std::max(1, static_cast<int>(std::ceil(reach / bw)));
  std::vector<int> bins(nbins, 0);
  const double in2 = (r_ref + tol) * (r_ref + tol);
  for (const Eigen::Vector3d& q : rel) {
    const double t = q.dot(u);
    if (t < 0 || t >= reach) continue;
    if (q.squaredNorm() - t * t <= in2) ++bins[std::min(nbins - 1, static_cast<int>(t / bw))];
  }
  std::vector<int> sorted(bins);
  std::sort(sorted.begin(), sorted.end());
  const int typical = std::max<int>(sorted[nbins / 2], static_cast<int>(expected_per_mm * bw * 0.5));
  const int empty_below = std::max(2, static_cast<int>(0.2 * typical));
  int run = 0;
  while (run < nbins && bins[run] >= empty_below) ++run;
  const double t_run = run * bw;
  double t_c;
  if (t_run >= std::min(reach, L + 0.5 * h)) {
    t_c = L;
  } else if (!bridging && t_run >= std::max(0.3 * L, 2.0 * ctx.resolution_mm)) {
    // the data end inside the last bin: refined below along the fitted axis
    const double w = std::max(2.0 * ctx.resolution_mm, 0.1 * L);
    t_c = dense_end(rel, Eigen::Vector3d::Zero(), u, r_ref, tol, t_run, w, std::max(6.0, 0.3 * expected_per_mm * w));
    if (t_c < std::max(0.3 * L, 2.0 * ctx.resolution_mm)) {
      st.fail = "no data";
      return st;
    }
    st.partial = true;
  } else {
    st.fail = "no data";
    return st;
  }
  // the fit window: around the new joint (full step) or ending at the data's end (partial)
  const double w0 = st.partial ? std::max(-h, t_c - 2 * h) : t_c - h;
  const double w1 = st.partial ? t_c : t_c + h;
  const double sel = r_ref + 3.5 * tol;  // wide enough to see the band outside the surface (below)
  std::vector<Eigen::Vector3d> win;
  std::vector<std::uint32_t> win_ids;
  for (std::size_t k = 0; k < rel.size(); ++k) {
    const Eigen::Vector3d& q = rel[k];
    const double t = q.dot(u);
    if (t < w0 || t > w1) continue;
    const double dd = (q - u * t).norm();
    if (dd <= sel && dd >= 0.3 * r_ref) {
      win.push_back(q);
      win_ids.push_back(rel_ids[k]);
    }
  }
  drop_facing_away(ctx, win, win_ids, u);
  if (win.size() < 8) {
    st.fail = "no data";
    return st;
  }
  CylinderFitResult fit = fit_cylinder(win, u * t_c, u, r_ref, ctx.fit_params(r_ref, a));
  if (!fit.ok) {
    st.fail = "no surface";
    return st;
  }
  if (std::abs(fit.radius_mm / r_ref - 1.0) > ctx.params.max_radius_change) {
    // A radius off by more than the limit ends the tube (it ran onto a clamp, a connector, a thicker
    // neighbour). In a sparse window (a thin tube in a sparse, noisy scan: a few points across, a 100 deg
    // arc, some tens of points) the radius is loose by 50 % and more while the axis stays well measured:
    // there the tube ends only when the data say so, i.e. the fit held at the tube's radius is clearly worse.
    // Dense windows keep the plain limit (on real scans, e.g. PCL's mug, their residuals are not Gaussian
    // enough for the test: the trace ran on over the rim).
    if (fit.inliers >= kSparseFitInliers) {
      st.fail = "radius jump";
      return st;
    }
    CylinderFitParams held = ctx.fit_params(r_ref, a);
    held.fix_radius = true;
    const CylinderFitResult fixed = fit_cylinder(win, u * t_c, u, r_ref, held);
    const double sigma2 = std::max(fit.rms_mm * fit.rms_mm, 1e-12);
    const double worse = (double(fixed.inliers) * fixed.rms_mm * fixed.rms_mm -
                          double(fit.inliers) * fit.rms_mm * fit.rms_mm) / sigma2;
    if (!fixed.ok || fixed.inliers < 0.8 * fit.inliers || worse > kRadiusChangeChi2) {
      st.fail = "radius jump";
      return st;
    }
    fit = fixed;
  }
  // continuity checks (4.2.4 robustness): never jump onto a neighbour, a plane or a crossing tube
  const double cos_turn = std::cos(ctx.params.max_turn_deg * M_PI / 180.0);
  if (fit.axis.dot(d) < cos_turn) {
    st.fail = "direction jump";
    return st;
  }
  // A thin tube along the sensor's rays: the depth errors between a front object's edge and what lies behind it
  // (mixed pixels) line up along the rays, and a fit holding a thin tube's radius follows them (a 1.7 mm wire
  // walked 11 mm up such a line to a wire crossing 16 mm above it). A tube seen so nearly end-on shows a dot
  // the size of its diameter, no surface to trace.
  if (ctx.thin && ctx.params.has_sensor) {
    const Eigen::Vector3d ray = (a + fit.point - ctx.params.sensor_position).normalized();
    if (std::abs(ray.dot(fit.axis)) > kThinAlongRayCos) {
      st.fail = "along the ray";
      return st;
    }
    // ... and one with something in front of it is no surface the sensor saw: the mixed pixels between a wire's
    // edge and the background behind it line up along the wire, in its shadow (a 1.9 mm wire traced 7 mm below
    // itself, and its own points then read as a foreign object 5.9 mm from it)
    if (!front_clear(ctx, a, fit.point, fit.axis, fit.radius_mm)) {
      st.fail = "hidden";
      return st;
    }
  }
  const Eigen::Vector3d foot_a = fit.point + fit.axis * fit.axis.dot(-fit.point);  // a is the origin here
  const double offset = foot_a.norm();
  const double max_offset = std::max(0.35 * r_ref, 2.0 * ctx.resolution_mm);
  if (offset > max_offset) {
    st.fail = "axis jump";
    return st;
  }
  const double win_len = w1 - std::max(w0, 0.0 - h);
  if (fit.inliers < std::max(8.0, 0.25 * expected_per_mm * win_len) || fit.arc_deg < std::max(45.0, 0.6 * arc_ref_deg)) {
    st.fail = "no surface";
    return st;
  }
  // the same surface as before: residuals like the tube's so far (a strip of a plane, a bundle of outliers
  // or another object's edge fit worse), and (paper 4.2.2: "an empty space around cables is assumed")
  // few points just outside the surface, where a plane or a touching object would continue
  const double rms_cap = 1.8 * rms_ref_mm + 0.05 * ctx.resolution_mm;
  if (fit.rms_mm > (ctx.thin ? rms_cap : std::min(0.25 * fit.radius_mm, rms_cap)) ||
      (bridging && fit.inliers < 0.5 * expected_per_mm * win_len)) {
    st.fail = "no surface";
    return st;
  }
  {
    const double b0 = fit.radius_mm + tol, b1 = fit.radius_mm + 3.0 * tol;
    const Eigen::Vector3d sensor = ctx.params.sensor_position - a;
    int band = 0, band_hidden = 0;
    for (const Eigen::Vector3d& q : win) {
      const Eigen::Vector3d v = q - fit.point;
      const double dd = (v - fit.axis * fit.axis.dot(v)).norm();
      if (dd <= b0 || dd > b1) continue;
      ++band;
      // a point the tube itself hides from the sensor is no surface beside it: a mixed pixel on a ray
      // grazing the silhouette (a veil hanging from it towards the background), not a plane going on
      if (hidden != HiddenPoints::Kept && behind_tube(sensor, q, fit.point, fit.axis, b0, 0.0, w0, w1)) ++band_hidden;
    }
    const double limit = 0.5 * fit.inliers;
    // the hidden points decide only where the tube is in front (checked above when any were dropped)
    if (band > limit && !(band - band_hidden <= limit && (hidden == HiddenPoints::Dropped ||
                                                          front_clear(ctx, a, fit.point, fit.axis, fit.radius_mm)))) {
      st.fail = "no surface";
      return st;
    }
  }
  st.ok = true;
  st.end = a + fit.point;  // the foot of a + u t_c on the fitted axis
  if (st.partial) {
    // the end along the fitted axis (the searched direction can be tilted where the data thin out)
    const double w = std::max(2.0 * ctx.resolution_mm, 0.1 * L);
    const double te = dense_end(rel, foot_a, fit.axis, fit.radius_mm, tol, t_run + 2.0 * bw, w,
                                std::max(6.0, 0.3 * expected_per_mm * w));
    if (te < 0.1 * L) {
      st.ok = false;
      st.fail = "no data";
      return st;
    }
    st.end = a + foot_a + fit.axis * te;
  }
  st.dir = fit.axis;
  st.radius_mm = fit.radius_mm;
  st.rms_mm = fit.rms_mm;
  st.arc_deg = fit.arc_deg;
  // the sub-cable's own points: inside its cylinder between a and the new joint
  const double out2 = (fit.radius_mm + tol) * (fit.radius_mm + tol);
  const Eigen::Vector3d seg = fit.point;
  const double len2 = seg.squaredNorm();
  std::uint32_t n = 0;
  for (const Eigen::Vector3d& q : rel) {
    const double t = len2 > 0 ? q.dot(seg) / len2 : 0.0;
    if (t < 0 || t > 1) continue;
    n += (q - seg * t).squaredNorm() <= out2;
  }
  st.points = n;
  return st;
}

}  // namespace ewis::tubes_detail
