// paper 4.2.1-4.2.2: the starting cylinder near a point on the tube's surface. The axis direction comes
// from the surface normals (perpendicular to a cylinder's axis), the centre and radius from a circle fit
// of the points projected along it; the paper's sphere of antipodal directions then picks the fullest
// cylinder through that centre, and a trimmed least-squares fit (4.2.3) refines it.
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "ewis/filter/normals.hpp"
#include "ewis/tubes/directions.hpp"
#include "tube_internal.hpp"

namespace ewis::tubes_detail {
namespace {

struct Estimate {
  bool ok = false;
  Eigen::Vector3d center, dir;
  double radius = 0;
};

// One estimate from the points within `rn` of p0.
Estimate estimate_in_ball(Context& ctx, const Eigen::Vector3d& p0, double rn) {
  Estimate e;
  std::vector<Eigen::Vector3d> rel;
  std::vector<std::uint32_t> ids;
  gather(ctx, p0, rn, p0, rel, &ids);
  if (rel.size() < 15) return e;
  // normals on an evenly strided subset (bounded work)
  const std::size_t stride = std::max<std::size_t>(1, ids.size() / 300);
  std::vector<std::uint32_t> sub;
  for (std::size_t i = 0; i < ids.size(); i += stride) sub.push_back(ids[i]);
  NormalParams np;
  np.k = 12;
  const std::vector<Eigen::Vector3f> normals = estimate_normals(ctx.tree, sub, np);
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (const auto& n : normals) m += n.cast<double>() * n.cast<double>().transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(m);
  // a cylinder's normals are all perpendicular to its axis: the eigenvector of the smallest eigenvalue
  const Eigen::Vector3d axis = es.eigenvectors().col(0);
  const Eigen::Matrix3d frame = rotation_from_z(axis);
  std::vector<Eigen::Vector2d> xy;
  xy.reserve(rel.size());
  for (const auto& q : rel) xy.emplace_back(q.dot(frame.col(0)), q.dot(frame.col(1)));
  const CircleFitResult c = fit_circle(xy, 2.5, std::max(0.02, 0.05 * ctx.resolution_mm));
  if (!c.ok) return e;
  e.ok = true;
  e.center = p0 + frame.col(0) * c.center.x() + frame.col(1) * c.center.y();
  e.dir = axis;
  e.radius = c.radius_mm;
  return e;
}

}  // namespace

bool initialise_at(Context& ctx, const Eigen::Vector3d& p0, double radius_hint, AxisState& out) {
  const double res = ctx.resolution_mm;
  const double max_rn = std::max(400.0 * res, 4.0 * radius_hint);
  double rn = radius_hint > 0 ? 1.5 * radius_hint : 8.0 * res;
  Estimate est;
  // grow or shrink the neighbourhood until it spans about 1.5 radii: a small patch of a big tube is flat
  for (int iter = 0; iter < 12 && rn <= max_rn; ++iter) {
    est = estimate_in_ball(ctx, p0, rn);
    if (!est.ok || est.radius > 3.0 * rn) {
      rn *= 2.0;
      est.ok = false;
      continue;
    }
    if (est.radius < rn / 2.5 && rn > 4.0 * res) {
      rn = std::max(1.5 * est.radius, 4.0 * res);
      continue;
    }
    break;
  }
  if (!est.ok) return false;
  double r = est.radius;
  if (radius_hint > 0 && (ctx.thin || r < 0.5 * radius_hint || r > 2.0 * radius_hint)) r = radius_hint;
  // paper 4.2.2: the sphere around the centre; antipodal pairs = candidate axes; the fullest cylinder wins
  // The window reaches +-max(r, 4 resolutions) along the axis, longer while it holds fewer than
  // kMinWindowPoints, up to +-12 resolutions: a thin tube in a sparse scan has a few points across, and the
  // starting fit (its radius and the arc it sees) needs some tens of them.
  constexpr std::size_t kMinWindowPoints = 60;
  const double tol0 = std::max(0.15 * r, 1.0 * res);
  double hl = std::max(r, 4.0 * res);
  std::vector<Eigen::Vector3d> rel;
  std::vector<std::uint32_t> ids;
  for (;;) {
    rel.clear();
    ids.clear();
    gather(ctx, est.center, std::sqrt(hl * hl + (r + 2 * tol0) * (r + 2 * tol0)), est.center, rel, &ids);
    if (rel.size() >= kMinWindowPoints || hl >= 12.0 * res) break;
    hl = std::min(1.5 * hl, 12.0 * res);
  }
  if (rel.size() < 15) return false;
  static const int kHemisphere = 600;  // ~5 deg apart
  const std::vector<Eigen::Vector3d> hemi = hemisphere_directions(kHemisphere);
  int score = 0;
  Eigen::Vector3d u = search_direction(ctx, rel, Eigen::Vector3d::UnitZ(), hemi, r, tol0, -hl, hl, score);
  // the normals' axis and the sphere's agree on a tube; keep whichever holds more of the surface
  {
    int s2 = 0;
    const Eigen::Vector3d u2 = search_direction(ctx, rel, est.dir, ctx.fine1, r, tol0, -hl, hl, s2);
    if (s2 >= score) u = u2;
  }
  std::vector<Eigen::Vector3d> win;
  std::vector<std::uint32_t> win_ids;
  for (std::size_t k = 0; k < rel.size(); ++k) {
    const Eigen::Vector3d& q = rel[k];
    const double t = q.dot(u);
    if (std::abs(t) > hl) continue;
    const double dd = (q - u * t).norm();
    if (dd <= r + 2 * tol0 && dd >= 0.3 * r) {
      win.push_back(q);
      win_ids.push_back(ids[k]);
    }
  }
  drop_facing_away(ctx, win, win_ids, u);
  CylinderFitParams fp = ctx.fit_params(r, est.center);
  fp.max_radius_mm = 3.0 * r;
  const CylinderFitResult fit = fit_cylinder(win, Eigen::Vector3d::Zero(), u, r, fp);
  if (!fit.ok || fit.arc_deg < 80.0 || fit.inliers < 20) return false;
  // a tube, not a noisy plane: the surface must bend well beyond the noise over the arc seen. A thin tube's
  // stripe cannot show that (TubeParams::thin_max_px): the radius is the hint's, and the steps' test of the empty
  // space around the tube stands for it.
  const double sagitta = fit.radius_mm * (1.0 - std::cos(0.5 * std::min(fit.arc_deg, 180.0) * M_PI / 180.0));
  if (!ctx.thin && (fit.rms_mm > 0.2 * fit.radius_mm || sagitta < 4.0 * fit.rms_mm)) return false;
  if (ctx.thin && !front_clear(ctx, est.center, fit.point, fit.axis, fit.radius_mm)) return false;  // (tube_step.cpp)
  const double ratio = std::max(1.0, ctx.params.max_seed_radius_ratio);
  if (radius_hint > 0 && (fit.radius_mm * ratio < radius_hint || fit.radius_mm > ratio * radius_hint)) return false;
  out.point = est.center + fit.point;
  out.dir = fit.axis;
  out.radius_mm = fit.radius_mm;
  out.rms_mm = fit.rms_mm;
  out.inliers = fit.inliers;
  out.window_mm = 2.0 * hl;
  out.arc_deg = fit.arc_deg;
  return true;
}

}  // namespace ewis::tubes_detail
