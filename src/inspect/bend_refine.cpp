// Tight bends re-measured on the surface points with the line-arc-line model (see fillet_fit.hpp).
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <utility>

#include "ewis/core/parallel.hpp"
#include "ewis/inspect/distance_gradient.hpp"
#include "ewis/inspect/fillet_fit.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis {
namespace {

struct Line {
  bool ok = false;
  Eigen::Vector3d point = Eigen::Vector3d::Zero(), direction = Eigen::Vector3d::UnitX();
};

// Least-squares line (PCA) through the centreline samples with arc length in [a, b].
Line fit_line(const std::vector<Eigen::Vector3d>& c, const std::vector<double>& arc, double a, double b) {
  Line l;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::size_t n = 0;
  for (std::size_t i = 0; i < c.size(); ++i)
    if (arc[i] >= a && arc[i] <= b) mean += c[i], ++n;
  if (n < 2) return l;
  mean /= double(n);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < c.size(); ++i)
    if (arc[i] >= a && arc[i] <= b) cov += (c[i] - mean) * (c[i] - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  l.point = mean;
  l.direction = es.eigenvectors().col(2).normalized();
  l.ok = es.eigenvalues()(2) > 0;
  return l;
}

Eigen::Vector3d at_arc(const std::vector<Eigen::Vector3d>& c, const std::vector<double>& arc, double s) {
  const auto it = std::lower_bound(arc.begin(), arc.end(), s);
  if (it == arc.begin()) return c.front();
  if (it == arc.end()) return c.back();
  const std::size_t i = std::size_t(it - arc.begin());
  const double len = arc[i] - arc[i - 1];
  const double t = len > 0 ? (s - arc[i - 1]) / len : 0.0;
  return c[i - 1] + t * (c[i] - c[i - 1]);
}

// Topographic prominence of every local maximum of v (0 elsewhere): its height above the higher of the two
// lowest points met on each side before a higher value (or the end of v).
std::vector<double> peak_prominence(const std::vector<double>& v) {
  std::vector<double> prom(v.size(), 0.0);
  for (std::size_t i = 0; i < v.size(); ++i) {
    if ((i > 0 && v[i - 1] > v[i]) || (i + 1 < v.size() && v[i + 1] >= v[i])) continue;
    double left = v[i], right = v[i];
    for (std::size_t j = i; j-- > 0;) {
      if (v[j] > v[i]) break;
      left = std::min(left, v[j]);
    }
    for (std::size_t j = i + 1; j < v.size(); ++j) {
      if (v[j] > v[i]) break;
      right = std::min(right, v[j]);
    }
    prom[i] = v[i] - std::max(left, right);
  }
  return prom;
}

// The points over a smooth tube's chord: those its fit uses.
std::vector<Eigen::Vector3d> over_chord(const std::vector<Eigen::Vector3d>& points, const SmoothTubeModel& m) {
  std::vector<Eigen::Vector3d> over;
  for (const Eigen::Vector3d& x : points)
    if (m.over_chord(x)) over.push_back(x);
  return over;
}

// The band around a first fit's surface in which a bend is fitted again on the scan (see FilletRefineParams::regather).
double regather_band(const FilletRefineParams& params, double sigma_mm, double tube_radius_mm) {
  return params.regather_band_mm > 0 ? params.regather_band_mm
                                     : std::max({3.0 * sigma_mm, 0.25 * tube_radius_mm, 0.5});
}

// The usable scan points within `reach` of `centre` that `keep` accepts (a model's surface band).
template <class Keep>
std::vector<Eigen::Vector3d> scan_points_near(const FilletScan& scan, const Eigen::Vector3d& centre, double reach,
                                              const Keep& keep) {
  std::vector<Neighbor> nb;
  scan.tree->radius(centre.cast<float>(), float(reach), nb);
  std::vector<Eigen::Vector3d> out;
  for (const Neighbor& n : nb) {
    if (scan.usable && n.index < scan.usable->size() && !(*scan.usable)[n.index]) continue;
    const Eigen::Vector3d x = scan.cloud->points[n.index].cast<double>();
    if (keep(x)) out.push_back(x);
  }
  return out;
}

// Whether x, on a tube around the centreline whose distance `dist` measures, faces the sensor: the outward
// direction from the axis turned towards it by a cosine of at least min_cos (see
// FilletRefineParams::facing_min_cos). Always true without a sensor.
template <class Dist>
bool faces_sensor(const FilletScan& scan, const Dist& dist, const Eigen::Vector3d& x, double min_cos) {
  return !scan.has_sensor || facing_cosine(dist, x, scan.sensor_position) >= min_cos;
}

// Where a fillet's arc meets its legs (leg 1's side first).
std::pair<Eigen::Vector3d, Eigen::Vector3d> fillet_tangent_points(const FilletModel& m) {
  const double tangent = m.bend_radius_mm * std::tan(0.5 * m.turn_rad());
  return {m.vertex + tangent * m.leg1, m.vertex + tangent * m.leg2};
}

// The distance of x from the line l.
double line_distance(const Line& l, const Eigen::Vector3d& x) {
  const Eigen::Vector3d r = x - l.point;
  return (r - r.dot(l.direction) * l.direction).norm();
}

// The middle of a fillet's arc.
Eigen::Vector3d fillet_arc_middle(const FilletModel& m) {
  const double half = 0.5 * m.turn_rad();
  return m.vertex + (m.leg1 + m.leg2).normalized() * (m.bend_radius_mm / std::cos(half) - m.bend_radius_mm);
}

struct Candidate {
  std::size_t profile = 0;
  double half_window_mm = 0.0;
};

}  // namespace

int fillet_leg_drifts(const FilletModel& m, const std::vector<Eigen::Vector3d>& pts, double kernel_mm,
                      const FilletRefineParams& params) {
  int drifting = 0;
  if (!(params.leg_drift_max_mm > 0)) return drifting;
  const FilletShape shape = fillet_shape(m);
  for (int leg = 0; leg < 2; ++leg) {
    const Eigen::Vector3d& start = leg == 0 ? shape.t1 : shape.t2;
    const Eigen::Vector3d dir = (leg == 0 ? shape.leg1 : shape.leg2).normalized();
    const Eigen::Vector3d e1 = dir.unitOrthogonal(), e2 = dir.cross(e1);
    // A point's residual against an axis moved by a + b t across the leg (t along it) changes by -normal . (a + b t)
    // (`normal`: the point's outward direction from the axis): the residuals regressed on that, and on a constant (the
    // tube's radius), by least squares. The drift is b's length over the leg; its significance b's chi-square (2 dof).
    Eigen::Matrix<double, 5, 5> ata = Eigen::Matrix<double, 5, 5>::Zero();
    Eigen::Matrix<double, 5, 1> atr = Eigen::Matrix<double, 5, 1>::Zero();
    double rr = 0, length = 0;
    std::size_t n = 0;
    for (const Eigen::Vector3d& x : pts) {
      const Eigen::Vector3d v = x - start;
      const double t = v.dot(dir);
      if (!(t > 0)) continue;
      const Eigen::Vector3d w = v - t * dir;
      const double dist = w.norm();
      const double r = dist - m.tube_radius_mm;
      if (!(dist > 0) || !(std::abs(r) <= 3.0 * kernel_mm)) continue;
      const double n1 = w.dot(e1) / dist, n2 = w.dot(e2) / dist;
      Eigen::Matrix<double, 5, 1> row;
      row << 1.0, -n1, -n2, -n1 * t, -n2 * t;
      ata += row * row.transpose();
      atr += row * r;
      rr += r * r;
      length = std::max(length, t);
      ++n;
    }
    if (n < std::max<std::size_t>(params.leg_drift_min_points, 6)) continue;
    const Eigen::LDLT<Eigen::Matrix<double, 5, 5>> ldlt(ata);
    if (ldlt.info() != Eigen::Success) continue;
    const Eigen::Matrix<double, 5, 1> coef = ldlt.solve(atr);
    const double sigma2 = std::max(rr - coef.dot(atr), 0.0) / double(n - 5);
    const Eigen::Vector2d b = coef.tail<2>();
    const Eigen::Matrix<double, 5, 5> cov = ldlt.solve(Eigen::Matrix<double, 5, 5>::Identity()) * sigma2;
    const Eigen::Matrix2d cov_b = cov.bottomRightCorner<2, 2>();
    if (!coef.allFinite() || !(cov_b.determinant() > 0)) continue;
    const double chi2 = b.dot(cov_b.ldlt().solve(b));
    if (b.norm() * length > params.leg_drift_max_mm && chi2 > params.leg_drift_min_z * params.leg_drift_min_z)
      drifting |= 1 << leg;
  }
  return drifting;
}

bool arc_goes_on_past_leg(const std::vector<Eigen::Vector3d>& centerline, const std::vector<double>& arc_mm,
                          double a_mm, double b_mm, const Eigen::Vector3d& tangent, const Eigen::Vector3d& leg,
                          const Eigen::Vector3d& other_tangent, double bend_radius_mm) {
  const Eigen::Vector3d chord = other_tangent - tangent, across = chord - chord.dot(leg) * leg;
  if (!(across.norm() > 1e-9) || !(bend_radius_mm > 0)) return true;
  const Eigen::Vector3d inward = across.normalized(), normal = leg.cross(inward);
  const Eigen::Vector3d centre = tangent + bend_radius_mm * inward;
  double circle_sq = 0.0, line_sq = 0.0;
  for (std::size_t i = 0; i < centerline.size() && i < arc_mm.size(); ++i) {
    if (!(arc_mm[i] > a_mm && arc_mm[i] < b_mm)) continue;
    const Eigen::Vector3d q = centerline[i] - centre, r = centerline[i] - tangent;
    const double h = q.dot(normal), radial = std::sqrt(std::max(q.squaredNorm() - h * h, 0.0)) - bend_radius_mm;
    circle_sq += radial * radial + h * h;
    line_sq += (r - r.dot(leg) * leg).squaredNorm();
  }
  return circle_sq < line_sq;
}

std::vector<std::uint8_t> arcs_cut_by_their_windows(const std::vector<FittedArc>& arcs, double run_length_mm,
                                                    double seen_mm) {
  const auto whole = [&](const FittedArc& a) {
    return a.arc_start_mm - a.window_start_mm >= seen_mm && a.window_end_mm - a.arc_end_mm >= seen_mm;
  };
  const double eps = 1e-9;
  std::vector<std::uint8_t> cut(arcs.size(), 0);
  for (std::size_t k = 0; k < arcs.size(); ++k) {
    const FittedArc& a = arcs[k];
    double ends[2];
    int n = 0;
    if (a.arc_start_mm - a.window_start_mm < seen_mm && a.window_start_mm > eps) ends[n++] = a.arc_start_mm;
    if (a.window_end_mm - a.arc_end_mm < seen_mm && a.window_end_mm < run_length_mm - eps) ends[n++] = a.arc_end_mm;
    for (int e = 0; e < n && !cut[k]; ++e)
      for (std::size_t j = 0; j < arcs.size() && !cut[k]; ++j)
        if (j != k && whole(arcs[j]) && arcs[j].radius_se_mm <= a.radius_se_mm && ends[e] > arcs[j].arc_start_mm &&
            ends[e] < arcs[j].arc_end_mm)
          cut[k] = 1;
  }
  return cut;
}

int refine_bends_with_fillets(BendRadiusResult& bend, const std::vector<Eigen::Vector3d>& centerline,
                              const std::vector<Eigen::Vector3d>& surface_points, double tube_radius_mm,
                              double diameter_mm, const FilletRefineParams& params, const FilletScan& scan) {
  if (!params.enabled || bend.profile.empty() || centerline.size() < 3 || surface_points.empty() ||
      !(tube_radius_mm > 0) || !(diameter_mm > 0))
    return 0;
  std::vector<double> arc(centerline.size(), 0.0);
  for (std::size_t i = 1; i < centerline.size(); ++i) arc[i] = arc[i - 1] + (centerline[i] - centerline[i - 1]).norm();
  const double total = arc.back();

  // Candidates: the tightest circle windows, one per bend (a later one must lie outside the earlier ones' windows).
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < bend.profile.size(); ++i)
    if (std::isfinite(bend.profile[i].radius_mm)) order.push_back(i);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return bend.profile[a].radius_mm < bend.profile[b].radius_mm; });
  std::vector<Candidate> cands;
  auto half_window = [&](std::size_t i) {
    const BendSample& p = bend.profile[i];
    return std::max(0.5 * (p.window_end_mm - p.window_start_mm) + params.leg_diameters * diameter_mm,
                    params.min_half_window_diameters * diameter_mm);
  };
  auto add_candidate = [&](std::size_t i) {
    const BendSample& p = bend.profile[i];
    const double half = half_window(i);
    for (const Candidate& c : cands) {
      const BendSample& q = bend.profile[c.profile];
      if (std::abs(q.arc_mm - p.arc_mm) < std::max(0.5 * (q.window_end_mm - q.window_start_mm), c.half_window_mm / 2) +
                                               diameter_mm)
        return;
    }
    cands.push_back({i, half});
  };
  // Corners first: a short tight bend reads nearly straight to the circle windows (its arc is a small part of
  // each), so it is found by how much the centreline turns within +-corner_span of a point (its peaks).
  {
    const double span = params.corner_span_diameters * diameter_mm;
    std::vector<double> turn(bend.profile.size(), 0.0);
    for (std::size_t i = 0; i < bend.profile.size(); ++i) {
      const double s = bend.profile[i].arc_mm;
      if (s - span < 0 || s + span > total) continue;
      const Eigen::Vector3d a = at_arc(centerline, arc, s) - at_arc(centerline, arc, s - span);
      const Eigen::Vector3d b = at_arc(centerline, arc, s + span) - at_arc(centerline, arc, s);
      if (a.norm() > 0 && b.norm() > 0) turn[i] = std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0));
    }
    // Ranked by prominence (how far the turn falls on each side before it rises to a higher peak): a long
    // arc's turn is a noisy plateau whose many local maxima have little prominence, while a short bend between
    // straights stands out by its whole turn. So one candidate per distinct bend, however long the others.
    const std::vector<double> prom = peak_prominence(turn);
    std::vector<std::size_t> peaks;
    for (std::size_t i = 0; i < turn.size(); ++i)
      if (prom[i] * 180.0 / M_PI >= params.corner_min_turn_deg) peaks.push_back(i);
    std::stable_sort(peaks.begin(), peaks.end(), [&](std::size_t a, std::size_t b) { return prom[a] > prom[b]; });
    for (std::size_t i : peaks) {
      if (int(cands.size()) >= params.max_corner_candidates) break;
      // Distinct peaks are distinct bends, even inside another bend's window; only one at the same place repeats.
      const bool repeated = std::any_of(cands.begin(), cands.end(), [&](const Candidate& c) {
        return std::abs(bend.profile[c.profile].arc_mm - bend.profile[i].arc_mm) < diameter_mm;
      });
      if (!repeated) cands.push_back({i, half_window(i)});
    }
  }
  const std::size_t corners = cands.size();
  for (std::size_t i : order) {
    if (int(cands.size() - corners) >= params.max_candidates) break;
    const BendSample& p = bend.profile[i];
    // Far looser than the tightest window: not the minimum, even if a fit read it a few times tighter.
    if (p.radius_mm > params.max_radius_ratio * bend.profile[order.front()].radius_mm) break;
    add_candidate(i);
  }

  if (cands.empty()) return 0;
  // Each surface point's nearest centreline sample (its arc length decides which windows it belongs to).
  std::vector<Eigen::Vector3f> cl(centerline.size());
  for (std::size_t i = 0; i < centerline.size(); ++i) cl[i] = centerline[i].cast<float>();
  const KdTree cl_tree(cl);
  std::vector<double> point_arc(surface_points.size(), -1.0);
  const double near_sq = (tube_radius_mm + 2.0) * (tube_radius_mm + 2.0);
  parallel_for_each_index(surface_points.size(), [&](std::size_t i) {
    const Neighbor nb = cl_tree.nearest(surface_points[i].cast<float>());
    if (nb.index != UINT32_MAX && double(nb.distance_sq) <= near_sq) point_arc[i] = arc[nb.index];
  }, 4096);

  struct Outcome {
    bool ok = false;
    FilletFit fit;
    bool bound = false;  // the radius is the loosest the data allow (fit.model.bend_radius_mm holds it)
    double bound_fit_mm = 0.0;  // a bound's: the free fit's radius, at least the tube's
    std::optional<FilletModel> init;  // the fillet's start (the legs from the centreline)
    bool smooth = false; // the smooth tube's radius replaces the fillet's (see FilletRefineParams::smooth)
    SmoothTubeFit smooth_fit;
    std::vector<Eigen::Vector3d> pts;  // the points the fillet was fitted on, and their noise scales (may be empty)
    std::vector<double> scales;
    double s0 = 0.0, s1 = 0.0;  // the window (arc length along the centreline)
    bool explained = false;  // another candidate's looser fillet explains this one's points (see below)
    bool cut = false;  // refused: its fillet's window cuts the bend (a leg unseen; see below)
    bool narrow = false;  // the fillet over the smooth tube's narrower window reads it (FilletRefineParams::narrow_*)
    FilletFit narrow_fit;
  };
  std::vector<Outcome> outcomes(cands.size());
  // The arc length of the centreline sample nearest to x (-1 when there is none).
  const auto arc_of = [&](const Eigen::Vector3d& x) {
    const Neighbor nb = cl_tree.nearest(x.cast<float>());
    return nb.index == UINT32_MAX ? -1.0 : arc[nb.index];
  };
  // The fillet over the window [s0, s1] (arc length): legs from the centreline's outer thirds, fitted on the window's
  // surface points, then again on the scan around the first fit's surface. `along` keeps the refit to scan points
  // whose nearest centreline sample lies in the window (a window trimmed short of a neighbouring bend; see
  // FilletRefineParams::leg_max_sagitta_mm). False when there is no corner to fit.
  const auto fit_window = [&](std::size_t k, double s0, double s1, bool along, Outcome& o) {
    const BendSample& p = bend.profile[cands[k].profile];
    o.s0 = s0;
    o.s1 = s1;
    // Legs from the centreline's outer thirds; the vertex where their lines pass closest.
    const double third = (s1 - s0) / 3.0;
    const Line l1 = fit_line(centerline, arc, s0, s0 + third), l2 = fit_line(centerline, arc, s1 - third, s1);
    if (!l1.ok || !l2.ok) return false;
    const Eigen::Vector3d d1 = l1.direction, d2 = l2.direction;
    const Eigen::Vector3d w0 = l1.point - l2.point;
    const double b = d1.dot(d2), den = 1.0 - b * b;
    if (den < 1e-6) return false;  // parallel legs: no corner to fit
    const double t1 = (b * d2.dot(w0) - d1.dot(w0)) / den, t2 = (d2.dot(w0) - b * d1.dot(w0)) / den;
    const Eigen::Vector3d q1 = l1.point + t1 * d1, q2 = l2.point + t2 * d2;
    FilletModel init;
    init.vertex = 0.5 * (q1 + q2);
    const Eigen::Vector3d centre = at_arc(centerline, arc, p.arc_mm);
    if ((init.vertex - centre).norm() > cands[k].half_window_mm) return false;
    init.leg1 = (at_arc(centerline, arc, s0) - init.vertex).normalized();
    init.leg2 = (at_arc(centerline, arc, s1) - init.vertex).normalized();
    if (!init.leg1.allFinite() || !init.leg2.allFinite() || init.turn_rad() < 1e-3) return false;
    init.bend_radius_mm = std::clamp(p.radius_mm, 0.5 * diameter_mm, 50.0 * diameter_mm);
    init.tube_radius_mm = tube_radius_mm;
    o.init = init;
    // The window's surface points: those whose nearest centreline sample lies inside it.
    std::vector<Eigen::Vector3d>& pts = o.pts;
    pts.clear();
    o.scales.clear();
    for (std::size_t i = 0; i < surface_points.size(); ++i)
      if (point_arc[i] >= s0 && point_arc[i] <= s1) pts.push_back(surface_points[i]);
    o.fit = fit_fillet(pts, init, params.fit);
    std::vector<double>& scales = o.scales;  // each point's noise relative to the others' (empty: the same for all)
    if (params.regather && scan.cloud && scan.tree && o.fit.ok) {
      // Again on the scan points around the first fit's surface (the corner's apex included).
      const FilletModel& m1 = o.fit.model;
      const double band = regather_band(params, o.fit.sigma_mm, tube_radius_mm);
      const FilletShape shape1 = fillet_shape(m1);
      const auto dist = [&](const Eigen::Vector3d& y) { return fillet_shape_distance(shape1, y); };
      std::vector<Eigen::Vector3d> again = scan_points_near(
          scan, m1.vertex, cands[k].half_window_mm + m1.tube_radius_mm + band, [&](const Eigen::Vector3d& x) {
            if (!(std::abs(dist(x) - m1.tube_radius_mm) <= band && faces_sensor(scan, dist, x, params.facing_min_cos)))
              return false;
            if (!along) return true;
            const double ax = arc_of(x);
            return ax >= s0 && ax <= s1;
          });
      std::vector<double> again_scales;
      if (scan.has_sensor && params.ray_noise_weights) again_scales = ray_noise_scales(again, m1, scan.sensor_position);
      const FilletFit second = fit_fillet(again, m1, params.fit, again_scales.empty() ? nullptr : &again_scales);
      if (second.ok) {
        o.fit = second;
        pts.swap(again);
        scales.swap(again_scales);
      }
    }
    return true;
  };
  // How far the centreline samples with arc length in [a, b] stray from the line `l` (its largest distance).
  const auto stray = [&](const Line& l, double a, double b) {
    double worst = 0.0;
    for (std::size_t i = 0; i < centerline.size(); ++i)
      if (arc[i] >= std::min(a, b) && arc[i] <= std::max(a, b))
        worst = std::max(worst, line_distance(l, centerline[i]));
    return worst;
  };
  // A leg from its tangent point `from` out to the window's end `to` (arc lengths) is bent when the centreline over
  // its outer quarter strays more than leg_limit from the leg's line. It is then cut where the centreline leaves the
  // line of the leg's near part (its first third, at least leg_min_diameters) by more than leg_limit, at the last
  // sample before that within a third of it (where the next bend begins, about). Returns the leg's end.
  const double leg_limit = std::max(params.leg_max_sagitta_mm, params.leg_sagitta_noise_factor * bend.noise_mm);
  const auto straight_leg_end = [&](double from, double to) {
    const double dir = to > from ? 1.0 : -1.0;
    const double near_end = from + dir * std::max(params.leg_min_diameters * diameter_mm, std::abs(to - from) / 3.0);
    if (dir * (to - near_end) <= 0) return to;
    // Bent: its outer quarter strays from the leg's line (a next bend grows away towards the end; a local wiggle
    // of the chain, at a clamp, does not).
    const Line whole = fit_line(centerline, arc, std::min(from, to), std::max(from, to));
    if (!whole.ok || stray(whole, to - 0.25 * (to - from), to) <= leg_limit) return to;
    const Line near = fit_line(centerline, arc, std::min(from, near_end), std::max(from, near_end));
    if (!near.ok) return to;
    double end = near_end, quiet = near_end;
    for (std::size_t j = 0; j < centerline.size(); ++j) {
      const std::size_t i = dir > 0 ? j : centerline.size() - 1 - j;
      if (dir * (arc[i] - near_end) <= 0) continue;
      if (dir * (arc[i] - to) > 0) break;
      const double e = line_distance(near, centerline[i]);
      if (e > leg_limit) return quiet;  // left the line: back to where it was still within a third of the limit
      if (e <= leg_limit / 3.0) quiet = arc[i];
      end = arc[i];
    }
    return end;
  };
  parallel_for_each_index(cands.size(), [&](std::size_t k) {
    const BendSample& p = bend.profile[cands[k].profile];
    const double s0 = std::max(0.0, p.arc_mm - cands[k].half_window_mm);
    const double s1 = std::min(total, p.arc_mm + cands[k].half_window_mm);
    Outcome& o = outcomes[k];
    if (!fit_window(k, s0, s1, false, o)) return;
    // Legs that bend (the window reaching into a neighbouring bend): again over their straight parts only, and once
    // more from that fit's tangent points (the first, pulled by the bent leg, misplaces them).
    for (int pass = 0;
         pass < 2 && params.leg_max_sagitta_mm > 0 && o.fit.ok && std::isfinite(o.fit.model.bend_radius_mm); ++pass) {
      const auto [p1, p2] = fillet_tangent_points(o.fit.model);
      const double t1 = arc_of(p1), t2 = arc_of(p2);
      if (t1 < 0 || t2 < 0) break;
      const double a1 = std::min(t1, t2), a2 = std::max(t1, t2);
      const double w0 = o.s0, w1 = o.s1;
      const double e0 = a1 > w0 ? straight_leg_end(a1, w0) : w0, e1 = a2 < w1 ? straight_leg_end(a2, w1) : w1;
      if (!(e0 > w0 + 1e-9 || e1 < w1 - 1e-9)) break;
      Outcome t;
      const bool fitted = fit_window(k, e0, e1, true, t);
      o = std::move(t);
      if (!fitted) return;  // no corner over the straight legs: the circle figure stands
    }
    // Both legs seen (FilletRefineParams::min_seen_leg_diameters): a leg shorter than that inside the window is
    // judged on the centreline past the window's end, from its tangent point over min_seen_leg_reach_diameters, which
    // must be there and straight.
    if (o.fit.ok && std::isfinite(o.fit.model.bend_radius_mm)) {
      const auto [p1, p2] = fillet_tangent_points(o.fit.model);
      const double t1 = arc_of(p1), t2 = arc_of(p2);
      const double lo = std::min(t1, t2), hi = std::max(t1, t2);
      const double seen = params.min_seen_leg_diameters * diameter_mm;
      // The leg from `tangent` along `leg` (unit, away from the arc); `other` is the arc's other tangent point.
      const auto unseen = [&](double from, double to, const Eigen::Vector3d& tangent, const Eigen::Vector3d& leg,
                              const Eigen::Vector3d& other) {
        if (!(std::abs(to - from) > 0 && std::abs(to - from) < seen)) return false;  // beyond the window, or long enough
        const double reach = from + (to > from ? 1.0 : -1.0) * params.min_seen_leg_reach_diameters * diameter_mm;
        if (reach < 0.0 || reach > total) return true;  // the run ends first
        const double a = std::min(from, reach), b = std::max(from, reach);
        const Line l = fit_line(centerline, arc, a, b);
        if (l.ok && stray(l, from, reach) <= leg_limit) return false;  // straight on past the window
        // Not straight: the arc goes on past the window (refused), or the short leg is a short straight into the
        // next bend (kept).
        return arc_goes_on_past_leg(centerline, arc, a, b, tangent, leg, other, o.fit.model.bend_radius_mm);
      };
      const bool first_low = t1 <= t2;
      const Eigen::Vector3d &p_lo = first_low ? p1 : p2, &p_hi = first_low ? p2 : p1;
      const Eigen::Vector3d &leg_lo = first_low ? o.fit.model.leg1 : o.fit.model.leg2,
                            &leg_hi = first_low ? o.fit.model.leg2 : o.fit.model.leg1;
      // Refused as a fillet reading: its window cuts the bend (another's may hold it). The fit stays as the rival of
      // the candidate's smooth tube, which is tried where no other fillet holds the place
      // (FilletRefineParams::smooth_cut_unheld).
      if (t1 >= 0 && t2 >= 0 && lo > o.s0 && hi < o.s1 &&
          (unseen(lo, o.s0, p_lo, leg_lo, p_hi) || unseen(hi, o.s1, p_hi, leg_hi, p_lo))) {
        o.cut = true;
        return;
      }
      // A leg that parts from its points (FilletRefineParams::leg_drift_*), running to the centreline's end: the
      // window's end on its side is brought in to half the leg and the fillet fitted again; the refit is taken where
      // its leg lies along its points, else the first fit stands.
      const auto kernel = [&](const FilletFit& f) {
        return params.fit.kernel_factor * std::max(f.sigma_mm, params.fit.min_noise_mm);
      };
      // The legs judged: both with leg_drift_inside, else one running to the centreline's end.
      const bool start_reached = o.s0 <= 1e-9, end_reached = o.s1 >= total - 1e-9;
      int judged = params.leg_drift_inside ? 3 : 0;
      if ((first_low && start_reached) || (!first_low && end_reached)) judged |= 1;  // leg 1 runs to that end
      if ((first_low && end_reached) || (!first_low && start_reached)) judged |= 2;
      if (const int drifting = judged ? fillet_leg_drifts(o.fit.model, o.pts, kernel(o.fit), params) & judged : 0) {
        double e0 = o.s0, e1 = o.s1;
        for (int leg = 0; leg < 2; ++leg) {
          if (!(drifting & (1 << leg))) continue;
          const double from = leg == 0 ? t1 : t2;
          if ((leg == 0) == first_low)  // the leg runs towards the window's start
            e0 = std::max(e0, from - 0.5 * std::max(from - o.s0, 0.0));
          else
            e1 = std::min(e1, from + 0.5 * std::max(o.s1 - from, 0.0));
        }
        Outcome t;
        if (t1 >= 0 && t2 >= 0 && e1 > e0 && fit_window(k, e0, e1, true, t) && t.fit.ok &&
            std::isfinite(t.fit.model.bend_radius_mm) &&
            !(fillet_leg_drifts(t.fit.model, t.pts, kernel(t.fit), params) & judged))
          o = std::move(t);
      }
    }
    const Eigen::Vector3d centre = at_arc(centerline, arc, p.arc_mm);
    const FilletModel& init = *o.init;
    std::vector<Eigen::Vector3d>& pts = o.pts;
    std::vector<double>& scales = o.scales;
    FilletFit& f = o.fit;
    // A corner the fit drew to a point: its radius under the tube's, where the data no longer change with it (the
    // radius's variance unbounded). The fit of a kink whose arc the scan hardly shows (C scene_001: 13.8 deg of
    // 21.45 mm on a 13.7 mm cable, right after a stretch another cable hides) ends there as readily as at a small
    // finite radius; either way no fit pins the radius down, and the bound below decides it.
    const bool collapsed = std::isfinite(f.model.bend_radius_mm) && f.model.bend_radius_mm < f.model.tube_radius_mm &&
                           !std::isfinite(f.bend_radius_se_mm);
    // The shape of a bend (a fit that did not converge may still bound the radius: see below).
    const double init_turn_deg = init.turn_rad() * 180.0 / M_PI, fit_turn_deg = f.model.turn_rad() * 180.0 / M_PI;
    const bool shaped = std::isfinite(f.model.bend_radius_mm) && (std::isfinite(f.bend_radius_se_mm) || collapsed) &&
                        fit_turn_deg >= params.min_turn_deg &&
                        fit_turn_deg - init_turn_deg <=
                            std::max(params.max_turn_excess_deg, params.max_turn_excess_fraction * init_turn_deg) &&
                        std::abs(f.model.tube_radius_mm - tube_radius_mm) <= params.tube_radius_tolerance * tube_radius_mm &&
                        (f.model.vertex - centre).norm() <= cands[k].half_window_mm &&
                        f.model.bend_radius_mm <= 100.0 * diameter_mm;
    if (!shaped) return;
    // A fit stopped by its iteration limit with its radius settled (inside a long arc the legs lie beyond the window
    // and the vertex slides along a flat direction) counts as converged when a second run from it leaves the radius
    // where it was and it is known to narrow_max_se_fraction, as the narrower fillet (below); otherwise the circle
    // windows' figure would stand for a bend the surface measures well. It is taken as it is only where it does not
    // read tighter than the circle windows by more than two of its standard errors; tighter, the data must prefer
    // it as they must an imprecise fit's.
    bool settled = false;
    if (!f.ok && params.settle_unconverged) {
      FilletFit again = fit_fillet(pts, f.model, params.fit, scales.empty() ? nullptr : &scales);
      if (std::isfinite(again.model.bend_radius_mm) && std::isfinite(again.bend_radius_se_mm) &&
          again.model.turn_rad() > 1e-3 && again.model.tube_radius_mm > 0 &&
          std::abs(again.model.bend_radius_mm - f.model.bend_radius_mm) <= 0.05 * again.bend_radius_se_mm &&
          again.bend_radius_se_mm <= params.narrow_max_se_fraction * again.model.bend_radius_mm &&
          (again.model.vertex - centre).norm() <= cands[k].half_window_mm) {
        f = std::move(again);
        settled = true;
      }
    }
    // A precise fit is taken as it is; a looser one (a short arc of a thin cable holds few points) only where it
    // shows the circle windows reading high by more than two of its standard errors (they cut short corners).
    // Tighter than the tube's radius the inside would fold into itself: such a fit (a short kink, whose radius
    // the data hardly constrain) is never taken as it is.
    const double se = f.bend_radius_se_mm, R = f.model.bend_radius_mm;
    const bool physical = R >= f.model.tube_radius_mm;
    const bool converged = f.ok || settled;
    if (physical && se <= params.max_se_fraction * R && (f.ok || (settled && !(p.radius_mm - R > 2.0 * se)))) {
      f.ok = true;
      o.ok = true;
      return;
    }
    if (!collapsed && !(p.radius_mm - R > 2.0 * se)) return;
    // The competing hypothesis: the same model held at the circle windows' radius. The data must prefer
    // the fit's radius clearly (a wrong local minimum of a thin cable's fit does not).
    FilletFitParams held = params.fit;
    held.fit_bend_radius = false;
    const double c = params.fit.kernel_factor * std::max(f.sigma_mm, params.fit.min_noise_mm);
    const double sigma2 = std::max(f.sigma_mm * f.sigma_mm * f.noise_inflation, 1e-12);
    const std::vector<double>* sc = scales.empty() ? nullptr : &scales;
    const double best_cost = fillet_robust_cost(pts, f.model, c, sc);
    // 2 x the robust cost's rise over the free fit's, held at radius r: a likelihood ratio (chi-square, 1 dof).
    auto ratio_at = [&](double r) {
      FilletModel start = f.model;
      start.bend_radius_mm = r;
      return 2.0 * (fillet_robust_cost(pts, fit_fillet(pts, start, held, sc).model, c, sc) - best_cost) / sigma2;
    };
    const double circle_r = std::clamp(p.radius_mm, f.model.tube_radius_mm, 100.0 * diameter_mm);
    if (ratio_at(circle_r) < params.min_log_likelihood_ratio) return;
    // ... and the data must pin the radius down on the loose side too: held at twice the fit's radius the
    // model must fit clearly worse. A corner fitted into a gently curving stretch (the circle windows there
    // reading high) is preferred to the circle's radius, but not to twice its own.
    if (converged && physical && se <= params.max_se_fraction_vs_circle * R &&
        ratio_at(2.0 * R) >= params.min_log_likelihood_ratio_doubled) {
      f.ok = true;
      o.ok = true;
      return;
    }
    // Not pinned (or tighter than the tube): the bend is then reported at the loosest radius the data still allow,
    // where the likelihood ratio reaches bound_log_likelihood_ratio (between the fit's radius and the circle
    // windows', which the data reject): an upper bound. A short kink is tighter than that, and a check against a
    // limit above it fails; a corner fitted into a gentle curve reads no tighter than its data say. A fit that did
    // not converge (a kink's radius drifting towards zero, where the data hardly change) bounds it too: its cost is
    // above the true minimum, so every ratio reads low and the bound lies looser still.
    // A kink turns as the centreline does across the window: a fit turning otherwise has its legs on something
    // else (a run's end at a connector: 62 and 80 deg fitted where the centreline turns 6-7 deg, on two campaign
    // scenes), and is no bend. The tightest physical radius must stay allowed too: a fit that rejects even the
    // tube's radius is the wrong model there.
    const double turn_deg = f.model.turn_rad() * 180.0 / M_PI, centreline_turn_deg = init.turn_rad() * 180.0 / M_PI;
    if (std::abs(turn_deg - centreline_turn_deg) >
        std::max(params.bound_turn_tolerance_deg, params.bound_turn_tolerance * centreline_turn_deg))
      return;
    const double low = std::max(R, f.model.tube_radius_mm);
    if (!physical && ratio_at(low) >= params.bound_log_likelihood_ratio) return;
    double lo = low, hi = circle_r;
    for (int it = 0; it < params.bound_iterations && hi > lo * (1.0 + 1e-3); ++it) {
      const double mid = std::sqrt(lo * hi);
      (ratio_at(mid) >= params.bound_log_likelihood_ratio ? hi : lo) = mid;
    }
    f.model.bend_radius_mm = hi;
    // Its standard error: the distance to the free fit over the bound's number of standard errors.
    f.bend_radius_se_mm = (hi - std::min(R, hi)) / std::sqrt(params.bound_log_likelihood_ratio);
    o.bound_fit_mm = std::min(low, hi);
    o.bound = true;
    o.ok = true;
  }, 1);

  // A smooth tube over the candidate (see FilletRefineParams::smooth), against the fillet on the same points.
  const auto smooth_candidate = [&](const BendSample& p, Outcome& o) {
    if (!o.init) return;  // no fillet to weigh the smooth tube against
    if (o.cut) {
      if (!params.smooth_cut_unheld) return;
      // Refused for a leg unseen: the smooth tube only where no other candidate's fillet reading (as the fillets
      // stand, before any smooth tube) holds the place between its tangent points, a diameter either side.
      for (std::size_t j = 0; j < outcomes.size(); ++j) {
        const Outcome& l = outcomes[j];
        if (&l == &o || !l.ok || l.bound || l.cut) continue;
        const auto [p1, p2] = fillet_tangent_points(l.fit.model);
        const double t1 = arc_of(p1), t2 = arc_of(p2);
        if (t1 >= 0 && t2 >= 0 && p.arc_mm >= std::min(t1, t2) - diameter_mm && p.arc_mm <= std::max(t1, t2) + diameter_mm)
          return;
      }
    }
    double rc = p.radius_mm;
    if (o.fit.ok && std::isfinite(o.fit.model.bend_radius_mm)) rc = std::min(rc, o.fit.model.bend_radius_mm);
    // +-smooth_window_radius_fraction x rc, at least smooth_min_half_window_diameters, at most max_diameters
    const auto half_window = [&](double max_diameters) {
      const double lo = params.smooth_min_half_window_diameters * diameter_mm;
      return std::clamp(params.smooth_window_radius_fraction * rc, lo, std::max(lo, max_diameters * diameter_mm));
    };
    const double h = half_window(params.smooth_max_half_window_diameters);
    double centre_s = p.arc_mm;
    SmoothTubeFit sf;
    std::vector<Eigen::Vector3d> pts;
    // The smooth tube over +-hw around centre_s, refitted on the scan points around it; false where it fails.
    const auto fit_window = [&](double centre, double hw, SmoothTubeFit& out, std::vector<Eigen::Vector3d>& out_pts) {
      const double s0 = std::max(0.0, centre - hw), s1 = std::min(total, centre + hw);
      if (s1 - s0 < hw) return false;  // at a run's end: no room for the window
      std::vector<Eigen::Vector3d> window;
      for (std::size_t i = 0; i < centerline.size(); ++i)
        if (arc[i] > s0 && arc[i] < s1) window.push_back(centerline[i]);
      out_pts.clear();
      for (std::size_t i = 0; i < surface_points.size(); ++i)
        if (point_arc[i] >= s0 - diameter_mm && point_arc[i] <= s1 + diameter_mm) out_pts.push_back(surface_points[i]);
      const bool again_on_scan = params.regather && scan.cloud && scan.tree;
      SmoothTubeFitParams first = params.smooth_fit;
      if (again_on_scan) first.max_iterations = std::min(first.max_iterations, 10);  // a start for the refit
      out = fit_smooth_tube(out_pts, window, at_arc(centerline, arc, s0), at_arc(centerline, arc, s1), tube_radius_mm,
                            first);
      if (!(out.model.tube_radius_mm > 0) || !std::isfinite(out.bend_radius_mm) || (!again_on_scan && !out.ok))
        return false;
      if (again_on_scan) {
        // Again on the scan points around the first fit's surface (a tight bend's outer side included).
        const SmoothTubeModel& m1 = out.model;
        const double band = regather_band(params, out.sigma_mm, tube_radius_mm);
        const auto dist = [&](const Eigen::Vector3d& y) { return smooth_tube_centreline_distance(m1, y); };
        const double reach = std::hypot(m1.half_chord_mm, hw) + m1.tube_radius_mm + band;
        std::vector<Eigen::Vector3d> again = scan_points_near(scan, m1.origin, reach, [&](const Eigen::Vector3d& x) {
          return m1.over_chord(x) && std::abs(dist(x) - m1.tube_radius_mm) <= band &&
                 faces_sensor(scan, dist, x, params.facing_min_cos);
        });
        SmoothTubeFit second = fit_smooth_tube_from(again, m1, params.smooth_fit);
        if (!second.ok) return false;
        out = std::move(second);
        out_pts.swap(again);
      }
      return true;
    };
    for (int pass = 0; pass < 2; ++pass) {
      if (!fit_window(centre_s, h, sf, pts)) return;
      // A peak near the window's edge: once more, centred on it.
      if (pass == 0 && std::abs(sf.peak_tau) > 0.8 * params.smooth_fit.peak_fraction) {
        const Neighbor nb = cl_tree.nearest(sf.peak_point.cast<float>());
        if (nb.index == UINT32_MAX) break;
        centre_s = arc[nb.index];
        continue;
      }
      break;
    }
    // A wider window where the candidate's radius allows it (thin cables: the window in diameters is short against
    // a broad peak), centred on the first one's peak and with its own peak in its middle, taken when its model
    // explains the narrower window's points about as well as that window's own fit and the two radii agree (see
    // FilletRefineParams::smooth_wide_*).
    const double h_wide = half_window(params.smooth_wide_max_half_window_diameters);
    double h_used = h;  // the half window sf was fitted over
    if (params.smooth_wide_max_half_window_diameters > 0 && h_wide > 1.25 * h) {
      SmoothTubeFit wide;
      std::vector<Eigen::Vector3d> wide_pts;
      const Neighbor nb = cl_tree.nearest(sf.peak_point.cast<float>());
      if (nb.index != UINT32_MAX && fit_window(arc[nb.index], h_wide, wide, wide_pts) &&
          std::abs(wide.peak_tau) <= 0.8 * params.smooth_fit.peak_fraction) {
        const std::vector<Eigen::Vector3d> narrow_over = over_chord(pts, sf.model);
        const double cn = params.fit.kernel_factor * std::max(sf.sigma_mm, params.fit.min_noise_mm);
        const double s2 = std::max(sf.sigma_mm * sf.sigma_mm * sf.noise_inflation, 1e-12);
        const double lack = 2.0 * (smooth_tube_robust_cost(narrow_over, wide.model, cn) -
                                   smooth_tube_robust_cost(narrow_over, sf.model, cn)) / s2;
        const double sn = sf.bend_radius_se_mm, sw = wide.bend_radius_se_mm;
        const double sd = std::sqrt(std::max(sn * sn - sw * sw, 0.25 * sn * sn));
        if (lack <= params.smooth_wide_max_log_likelihood_ratio &&
            std::abs(wide.bend_radius_mm - sf.bend_radius_mm) <= params.smooth_wide_max_z * sd) {
          sf = std::move(wide);
          pts.swap(wide_pts);
          h_used = h_wide;
        }
      }
    }
    const double R = sf.bend_radius_mm;
    // A smooth fit that can stand for the bend: its radius known to `se_fraction`, its tube the run's (within
    // smooth_tube_radius_tolerance), its peak away from the run's ends (smooth_min_end_diameters) and seen on both
    // sides (smooth_peak_seen_*) by its points `fp`.
    const double end_reach = params.smooth_min_end_diameters * diameter_mm;
    const auto peak_seen = [&](const SmoothTubeFit& f, const std::vector<Eigen::Vector3d>& fp) {
      if (!(params.smooth_peak_seen_fraction > 0)) return true;
      const double side = params.smooth_peak_seen_diameters * diameter_mm;
      std::size_t over = 0, before = 0, after = 0;
      for (const Eigen::Vector3d& x : fp) {
        if (!f.model.over_chord(x)) continue;
        ++over;
        const double a = f.model.u.dot(x - f.peak_point);
        before += a > -side && a <= 0.0;
        after += a > 0.0 && a < side;
      }
      const double expected = double(over) * side / (2.0 * f.model.half_chord_mm);
      return double(std::min(before, after)) >= params.smooth_peak_seen_fraction * expected;
    };
    const auto usable = [&](const SmoothTubeFit& f, const std::vector<Eigen::Vector3d>& fp, double se_fraction) {
      const double peak_arc = arc_of(f.peak_point);
      return f.bend_radius_mm <= 100.0 * diameter_mm && f.bend_radius_mm >= f.model.tube_radius_mm &&
             f.bend_radius_se_mm <= se_fraction * f.bend_radius_mm &&
             std::abs(f.model.tube_radius_mm - tube_radius_mm) <= params.smooth_tube_radius_tolerance * tube_radius_mm &&
             peak_arc >= end_reach && peak_arc <= total - end_reach && peak_seen(f, fp);
    };
    const bool smooth_usable = usable(sf, pts, std::min(params.max_se_fraction, params.smooth_max_se_fraction));
    // The fillet on the same points (those over the smooth tube's chord), from its own fit when it has one.
    const std::vector<Eigen::Vector3d> over = over_chord(pts, sf.model);
    const bool fillet_shaped = std::isfinite(o.fit.model.bend_radius_mm) && o.fit.model.turn_rad() > 1e-3 &&
                               o.fit.model.tube_radius_mm > 0;
    const FilletModel& start = fillet_shaped ? o.fit.model : *o.init;
    const double c = params.fit.kernel_factor * std::max(sf.sigma_mm, params.fit.min_noise_mm);
    const double sigma2 = std::max(sf.sigma_mm * sf.sigma_mm * sf.noise_inflation, 1e-12);
    const double smooth_cost = smooth_tube_robust_cost(over, sf.model, c);
    // The fillet over the narrower window where it reads clearly tighter (see FilletRefineParams::narrow_min_z).
    std::optional<FilletFit> rival_early;
    if (params.narrow_min_z > 0 && fillet_shaped && o.fit.ok && !o.bound && !o.cut) {
      rival_early = fit_fillet(over, start, params.fit);
      FilletFit n = *rival_early;
      // A fit stopped by its iteration limit with its radius settled (a flat direction of the vertex or a leg
      // still creeping) is taken when a second run from it leaves the radius where it was.
      bool settled = n.ok;
      if (!settled && std::isfinite(n.model.bend_radius_mm) && n.model.turn_rad() > 1e-3) {
        FilletFit again = fit_fillet(over, n.model, params.fit);
        settled = std::isfinite(again.model.bend_radius_mm) && again.model.turn_rad() > 1e-3 &&
                  std::abs(again.model.bend_radius_mm - n.model.bend_radius_mm) <= 0.05 * again.bend_radius_se_mm;
        if (settled) n = std::move(again);
      }
      const double rw = o.fit.model.bend_radius_mm, rn = n.model.bend_radius_mm;
      const double sw = o.fit.bend_radius_se_mm, sn = n.bend_radius_se_mm;
      const double sd = std::sqrt(std::max(sn * sn - sw * sw, 0.25 * sn * sn));
      o.narrow = settled && rn >= n.model.tube_radius_mm && sn <= params.narrow_max_se_fraction * rn &&
                 rw - rn >= params.narrow_min_z * sd;
      if (o.narrow) o.narrow_fit = std::move(n);
    }
    if (!smooth_usable) return;
    // The fillet as it stands first: refitted on these points it can only fit better, so a ratio already short of
    // the threshold needs no refit (most candidates; the refit is the costly part).
    const double min_ratio =
        std::min(params.smooth_min_log_likelihood_ratio, params.smooth_varying_min_log_likelihood_ratio);
    if (!(2.0 * (fillet_robust_cost(over, start, c) - smooth_cost) / sigma2 >= min_ratio)) return;
    const FilletFit rival = rival_early ? std::move(*rival_early) : fit_fillet(over, start, params.fit);
    const double rival_cost = fillet_robust_cost(over, rival.model, c);
    const double ratio = 2.0 * (rival_cost - smooth_cost) / sigma2;
    if (!(ratio >= min_ratio)) return;
    // Below the full threshold, only where the curvature varies: the fillet on the smooth tube's (narrower) points
    // reads clearly tighter than the candidate's own (see FilletRefineParams::smooth_varying_*).
    const bool full = ratio >= params.smooth_min_log_likelihood_ratio;
    if (!full) {
      const bool varies = o.fit.ok && rival.ok && std::isfinite(o.fit.model.bend_radius_mm) &&
                          o.fit.model.bend_radius_mm - rival.model.bend_radius_mm >=
                              params.smooth_varying_min_z * rival.bend_radius_se_mm;
      if (!varies) return;
    }
    // A peak more than 1 / smooth_min_fillet_ratio times the fillet's curvature on the same points is the quartic
    // wiggling, not a bend (see FilletRefineParams::smooth_min_fillet_ratio).
    if (!(R >= params.smooth_min_fillet_ratio * rival.model.bend_radius_mm)) return;
    // A bend out of its plane: where the fillet as a helix (its tilt free) fits about as well as the smooth tube, the
    // quartic won on the torsion, and it stands only where the curvature varies as the helices read it: the narrower
    // window's clearly tighter than the candidate's (see FilletRefineParams::smooth_tilted_rival).
    if (params.smooth_tilted_rival && std::isfinite(rival.model.bend_radius_mm)) {
      FilletFitParams tilted_params = params.fit;
      tilted_params.fit_tilt = true;
      const FilletFit tilted = fit_fillet(over, rival.model, tilted_params);
      const double tilted_ratio = 2.0 * (fillet_robust_cost(over, tilted.model, c) - smooth_cost) / sigma2;
      if (std::isfinite(tilted.model.bend_radius_mm) && tilted_ratio < params.smooth_tilted_max_log_likelihood_ratio) {
        const std::vector<double>* sc = o.scales.empty() ? nullptr : &o.scales;
        const FilletFit wide = fit_fillet(o.pts, o.fit.model, tilted_params, sc);
        const double tighter = wide.model.bend_radius_mm - tilted.model.bend_radius_mm;
        const bool varies = std::isfinite(tighter) && std::isfinite(tilted.bend_radius_se_mm) &&
                            tighter >= params.smooth_varying_min_z * tilted.bend_radius_se_mm &&
                            tighter >= params.smooth_tilted_min_variation * wide.model.bend_radius_mm;
        if (!varies) return;
      }
    }
    // Not its whole advantage in one stretch, the rest fitting worse (FilletRefineParams::smooth_spread_bins).
    if (params.smooth_spread_bins > 1) {
      const int bins = params.smooth_spread_bins;
      std::vector<std::vector<Eigen::Vector3d>> stretch(static_cast<std::size_t>(bins));
      for (const Eigen::Vector3d& x : over) {
        const int k = std::clamp(int(std::floor(0.5 * (sf.model.tau_of(x) + 1.0) * bins)), 0, bins - 1);
        stretch[std::size_t(k)].push_back(x);
      }
      std::vector<double> gains;
      for (const auto& pts_k : stretch)
        if (!pts_k.empty())
          gains.push_back(fillet_robust_cost(pts_k, rival.model, c) - smooth_tube_robust_cost(pts_k, sf.model, c));
      std::sort(gains.begin(), gains.end(), std::greater<>());
      double top = 0;
      const std::size_t top_bins = static_cast<std::size_t>(std::max(0, params.smooth_spread_top_bins));
      for (std::size_t k = 0; k < std::min(gains.size(), top_bins); ++k) top += std::max(0.0, gains[k]);
      if (!(ratio - 2.0 * top / sigma2 >= params.smooth_spread_min_log_likelihood_ratio)) return;
    }
    // Narrower windows around its peak, each taken where it reads clearly tighter (FilletRefineParams::smooth_narrow_*).
    const double h_min = params.smooth_narrow_min_half_window_diameters * diameter_mm;
    for (int step = 0; step < params.smooth_narrow_max_steps && h_used > h_min * (1.0 + 1e-9); ++step) {
      const double hn = std::max(params.smooth_narrow_factor * h_used, h_min);
      const Neighbor nb = cl_tree.nearest(sf.peak_point.cast<float>());
      SmoothTubeFit n;
      std::vector<Eigen::Vector3d> n_pts;
      if (nb.index == UINT32_MAX || !fit_window(arc[nb.index], hn, n, n_pts) ||
          std::abs(n.peak_tau) > 0.8 * params.smooth_fit.peak_fraction)
        break;
      const double sn = n.bend_radius_se_mm, sw = sf.bend_radius_se_mm;
      const double sd = std::sqrt(std::max(sn * sn - sw * sw, 0.25 * sn * sn));
      if (!usable(n, n_pts, params.smooth_narrow_max_se_fraction) ||
          !(sf.bend_radius_mm - n.bend_radius_mm >= params.smooth_narrow_min_z * sd))
        break;
      sf = std::move(n);
      h_used = hn;
    }
    o.smooth = true;
    o.smooth_fit = sf;
  };
  if (params.smooth) {
    parallel_for_each_index(cands.size(), [&](std::size_t k) {
      smooth_candidate(bend.profile[cands[k].profile], outcomes[k]);
    }, 1);
  }

  // A fillet tighter than another candidate's far more precise one, whose arc lies on that one's arc and whose radius
  // agrees with it, is a bend of its own only where its points there reject the looser fillet's model
  // (FilletRefineParams::explained_*).
  const auto fillet_reading = [&](const Outcome& o) { return o.ok && !o.bound && !o.smooth; };
  if (params.explained_min_log_likelihood_ratio > 0) {
    parallel_for_each_index(cands.size(), [&](std::size_t k) {
      Outcome& o = outcomes[k];
      if (!fillet_reading(o)) return;
      const double c = params.fit.kernel_factor * std::max(o.fit.sigma_mm, params.fit.min_noise_mm);
      const double sigma2 = std::max(o.fit.sigma_mm * o.fit.sigma_mm, 1e-12);
      std::vector<double> pts_arc;  // each point's arc length, found once a looser fillet qualifies
      const double mid_arc = arc_of(fillet_arc_middle(o.fit.model));
      for (std::size_t j = 0; j < cands.size() && !o.explained; ++j) {
        const Outcome& l = outcomes[j];
        if (j == k || !fillet_reading(l) || !(l.fit.model.bend_radius_mm > o.fit.model.bend_radius_mm) ||
            !(l.fit.bend_radius_se_mm <= params.explained_max_se_ratio * o.fit.bend_radius_se_mm))
          continue;
        // This arc's middle between the looser arc's tangent points (along the centreline).
        const FilletModel& m = l.fit.model;
        const auto [p1, p2] = fillet_tangent_points(m);
        const double t1 = arc_of(p1), t2 = arc_of(p2);
        if (!(mid_arc >= std::min(t1, t2) && mid_arc <= std::max(t1, t2))) continue;
        // The two radii agree within their errors (a spline's curvature peak read by the narrower fit does not).
        if (!(m.bend_radius_mm - o.fit.model.bend_radius_mm <
              params.explained_max_radius_z * std::hypot(o.fit.bend_radius_se_mm, l.fit.bend_radius_se_mm)))
          continue;
        // Both models on this fit's points inside the looser one's window (its model holds there only).
        if (pts_arc.empty())
          for (const Eigen::Vector3d& x : o.pts) pts_arc.push_back(arc_of(x));
        std::vector<Eigen::Vector3d> shared;
        std::vector<double> shared_scales;
        for (std::size_t i = 0; i < o.pts.size(); ++i) {
          if (pts_arc[i] < l.s0 || pts_arc[i] > l.s1) continue;
          shared.push_back(o.pts[i]);
          if (!o.scales.empty()) shared_scales.push_back(o.scales[i]);
        }
        if (2 * shared.size() < o.pts.size()) continue;
        const std::vector<double>* sc = shared_scales.empty() ? nullptr : &shared_scales;
        const double ratio =
            2.0 * (fillet_robust_cost(shared, m, c, sc) - fillet_robust_cost(shared, o.fit.model, c, sc)) /
            (sigma2 * o.fit.noise_inflation);
        o.explained = ratio < params.explained_min_log_likelihood_ratio;
      }
    }, 1);
  }

  // A fillet whose window cut its bend, which another candidate's fillet holds whole, is left out of the choice
  // (FilletRefineParams::cut_arcs_held_elsewhere; judged on the fillets as they stand, before any is left out).
  if (params.cut_arcs_held_elsewhere) {
    std::vector<FittedArc> arcs;
    std::vector<std::size_t> of;  // the candidate of each arc
    for (std::size_t k = 0; k < cands.size(); ++k) {
      const Outcome& o = outcomes[k];
      if (!fillet_reading(o)) continue;
      const auto [p1, p2] = fillet_tangent_points(o.fit.model);
      const double t1 = arc_of(p1), t2 = arc_of(p2);
      if (t1 < 0 || t2 < 0) continue;
      arcs.push_back({std::min(t1, t2), std::max(t1, t2), o.s0, o.s1, o.fit.bend_radius_se_mm});
      of.push_back(k);
    }
    const std::vector<std::uint8_t> cut =
        arcs_cut_by_their_windows(arcs, total, params.min_seen_leg_diameters * diameter_mm);
    for (std::size_t i = 0; i < arcs.size(); ++i)
      if (cut[i]) outcomes[of[i]].explained = true;
  }

  // A circle figure (a candidate no fit re-measured) at a run's end, on another candidate's fillet arc, reads that
  // bend from the centreline's last joints, whose errors the surface fit does not share: it is left out of the
  // choice unless the surface points of its window prefer its radius to the fillet's
  // (FilletRefineParams::circle_explained_*).
  if (params.circle_explained_min_log_likelihood_ratio > 0) {
    parallel_for_each_index(cands.size(), [&](std::size_t k) {
      Outcome& o = outcomes[k];
      if (o.ok || o.narrow || o.smooth) return;
      const BendSample& p = bend.profile[cands[k].profile];
      if (!std::isfinite(p.radius_mm)) return;
      const double end_reach = params.circle_explained_end_diameters * diameter_mm;
      // Away from the run's ends, only a window whose fillet was refused for cutting the bend.
      const bool cut = o.cut && params.circle_explained_cut;
      if (!cut && p.window_start_mm > end_reach && p.window_end_mm < total - end_reach) return;
      const double mid = 0.5 * (p.window_start_mm + p.window_end_mm);
      std::vector<std::size_t> own;  // the circle window's surface points
      for (std::size_t i = 0; i < surface_points.size(); ++i)
        if (point_arc[i] >= p.window_start_mm && point_arc[i] <= p.window_end_mm) own.push_back(i);
      for (std::size_t j = 0; j < cands.size() && !o.explained; ++j) {
        const Outcome& l = outcomes[j];
        if (j == k || !fillet_reading(l)) continue;
        const FilletModel& m = l.fit.model;
        const auto [p1, p2] = fillet_tangent_points(m);
        const double t1 = arc_of(p1), t2 = arc_of(p2);
        if (t1 < 0 || t2 < 0 || !(mid >= std::min(t1, t2) && mid <= std::max(t1, t2))) continue;
        std::vector<Eigen::Vector3d> shared;
        for (std::size_t i : own)
          if (point_arc[i] >= l.s0 && point_arc[i] <= l.s1) shared.push_back(surface_points[i]);
        if (shared.size() < params.circle_explained_min_points || 2 * shared.size() < own.size()) continue;
        // The fillet held at each radius, the rest of it fitted on these points: a likelihood ratio (1 dof).
        FilletFitParams held = params.fit;
        held.fit_bend_radius = false;
        const double c = params.fit.kernel_factor * std::max(l.fit.sigma_mm, params.fit.min_noise_mm);
        const double sigma2 = std::max(l.fit.sigma_mm * l.fit.sigma_mm * l.fit.noise_inflation, 1e-12);
        const auto cost_at = [&](double r) {
          FilletModel start = m;
          start.bend_radius_mm = r;
          const FilletFit f = fit_fillet(shared, start, held);
          return fillet_robust_cost(shared, std::isfinite(f.model.bend_radius_mm) ? f.model : start, c);
        };
        const double ratio = 2.0 * (cost_at(m.bend_radius_mm) - cost_at(p.radius_mm)) / sigma2;
        o.explained = ratio < params.circle_explained_min_log_likelihood_ratio;
      }
    }, 1);
  }

  // The minimum over the re-measured bends (a fit failing keeps its circle figure, unless explained), chosen on
  // radius + choice_se_factor x se: a loose arc wins over a tighter one only when it is tighter even then.
  int refined = 0;
  double best_score = std::numeric_limits<double>::infinity();
  std::optional<double> best_radius;
  double best_se = 0.0;
  Eigen::Vector3d best_location = Eigen::Vector3d::Zero();
  bool best_bound = false;
  double best_fit = 0.0;
  const char* best_model = "circle";
  for (std::size_t k = 0; k < cands.size(); ++k) {
    if (outcomes[k].explained) continue;  // the looser fillet that explains it is a candidate too
    const BendSample& p = bend.profile[cands[k].profile];
    double r = p.radius_mm, se = p.radius_se_mm;
    Eigen::Vector3d where = p.point;
    bool bound = false;
    double fit = 0.0;
    const char* model = "circle";
    if (outcomes[k].smooth) {
      model = "smooth";
      ++refined;
      r = outcomes[k].smooth_fit.bend_radius_mm;
      se = outcomes[k].smooth_fit.bend_radius_se_mm;
      where = outcomes[k].smooth_fit.peak_point;
    } else if (outcomes[k].ok || outcomes[k].narrow) {
      ++refined;
      bound = outcomes[k].bound;  // never with a narrower reading
      model = bound ? "bound" : "fillet";
      const FilletFit& f = outcomes[k].narrow ? outcomes[k].narrow_fit : outcomes[k].fit;
      r = f.model.bend_radius_mm;
      se = f.bend_radius_se_mm;
      where = fillet_arc_middle(f.model);
      if (bound) fit = outcomes[k].bound_fit_mm;
    }
    const double score = r + params.choice_se_factor * se;
    if (score < best_score) {
      best_score = score;
      best_radius = r;
      best_se = se;
      best_location = where;
      best_bound = bound;
      best_fit = fit;
      best_model = model;
    }
  }
  if (refined > 0 && best_radius) {
    bend.min_radius_mm = best_radius;
    bend.min_radius_se_mm = best_se;
    bend.location = best_location;
    bend.min_radius_is_bound = best_bound;
    bend.min_radius_fit_mm = best_bound ? best_fit : 0.0;
    bend.min_radius_model = best_model;
  }
  return refined;
}

}  // namespace ewis
