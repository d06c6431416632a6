// paper 4.3.2: interference detection (see interference.hpp for the rules).
#include "ewis/inspect/interference.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

#include "ewis/core/parallel.hpp"
#include "ewis/core/robust.hpp"
#include "ewis/filter/euclidean_clusters.hpp"
#include "ewis/filter/normals.hpp"
#include "ewis/filter/ray_neighbours.hpp"
#include "ewis/inspect/chain_distance.hpp"
#include "ewis/tubes/cylinder_fit.hpp"

namespace ewis {
namespace {

// What a candidate point lies on: kind 0 rigid element, 1 another cable, 2 nothing (foreign), 3 a mixed pixel.
struct Label {
  int kind = 2;
  int index = -1;
  bool operator<(const Label& o) const { return kind != o.kind ? kind < o.kind : index < o.index; }
};

// Length of the segment [a, b] inside the axis-aligned box [lo, hi] (slabs).
double segment_in_box_mm(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& lo,
                         const Eigen::Vector3d& hi) {
  const Eigen::Vector3d d = b - a;
  double t0 = 0, t1 = 1;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (a[k] < lo[k] || a[k] > hi[k]) return 0.0;
      continue;
    }
    double u0 = (lo[k] - a[k]) / d[k], u1 = (hi[k] - a[k]) / d[k];
    if (u0 > u1) std::swap(u0, u1);
    t0 = std::max(t0, u0);
    t1 = std::min(t1, u1);
    if (t0 >= t1) return 0.0;
  }
  return (t1 - t0) * d.norm();
}

// The longest break between a cable's runs that is bridged (see InterferenceParams::bridge_break_diameters).
double bridge_limit_mm(const InterferenceParams& params, double radius_mm) {
  return std::max(params.bridge_break_diameters * 2.0 * radius_mm, params.bridge_break_min_mm);
}

bool contains_sorted(const std::vector<std::uint32_t>& v, std::uint32_t x) {
  return std::binary_search(v.begin(), v.end(), x);
}

// The image footprint of a cluster seen from the sensor: each point projected along its own ray onto the plane across
// the ray through the cluster's mean (a perspective projection), on a grid of a quarter resolution, each cell once.
// Points on one ray are one pixel of the image: a sensor gives one depth per pixel, and a simulator may put many mixed
// points on an edge pixel's ray (campaign seed 5151: up to 60), which would otherwise count as an area.
struct Footprint {
  std::vector<Eigen::Vector2d> pixels;
  std::size_t stacked = 0;  // pixels holding points more than stack_min_spread_mm apart along their ray
  std::vector<std::uint8_t> on_stack;  // per point (in the cluster's order): its pixel is such a stack
};

Footprint image_footprint(const Cloud& cloud, const std::vector<std::uint32_t>& pts, const InterferenceParams& params) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::uint32_t i : pts) mean += cloud.points[i].cast<double>();
  mean /= double(std::max<std::size_t>(1, pts.size()));
  const Eigen::Vector3d view = (mean - params.sensor_position).normalized();
  const Eigen::Vector3d u = view.unitOrthogonal(), v = view.cross(u);
  const double pixel = 0.25 * std::max(params.resolution_mm, 1e-3);
  struct Hit {
    long a, b;
    double range;
    std::size_t k;  // the point's place in the cluster
    bool operator<(const Hit& o) const {
      return a != o.a ? a < o.a : b != o.b ? b < o.b : range != o.range ? range < o.range : k < o.k;
    }
  };
  std::vector<Hit> hits(pts.size());
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const Eigen::Vector3d x = cloud.points[pts[k]].cast<double>(), d = x - mean;
    const Eigen::Vector3d ray = (x - params.sensor_position).normalized();
    const double t = -d.dot(view) / std::max(ray.dot(view), 1e-6);
    hits[k] = {std::lround(std::floor((d + t * ray).dot(u) / pixel)), std::lround(std::floor((d + t * ray).dot(v) / pixel)),
               (x - params.sensor_position).norm(), k};
  }
  std::sort(hits.begin(), hits.end());
  Footprint f;
  f.on_stack.assign(pts.size(), 0);
  for (std::size_t i = 0; i < hits.size();) {
    std::size_t j = i;
    while (j < hits.size() && hits[j].a == hits[i].a && hits[j].b == hits[i].b) ++j;
    f.pixels.emplace_back((double(hits[i].a) + 0.5) * pixel, (double(hits[i].b) + 0.5) * pixel);
    if (hits[j - 1].range - hits[i].range > params.stack_min_spread_mm) {
      ++f.stacked;
      for (std::size_t h = i; h < j; ++h) f.on_stack[hits[h].k] = 1;
    }
    i = j;
  }
  return f;
}

// The local normals (PCA) of a cluster's points, turned towards the sensor (see is_veil).
std::vector<Eigen::Vector3f> local_normals(const KdTree& tree, const std::vector<std::uint32_t>& pts,
                                           const InterferenceParams& params) {
  NormalParams np;
  np.radius_mm = std::max(params.veil_radius_mm, 4.0 * params.resolution_mm);
  np.max_neighbors = 64;
  np.viewpoint = params.sensor_position.cast<float>();
  return estimate_normals(tree, pts, np);
}

// The points of a cluster whose surface faces the sensor (|cos| of normal and ray at least veil_facing_cos), not on a
// stacked pixel (image_footprint: no surface gives several depths on one ray), sorted.
std::vector<std::uint32_t> facing_points(const KdTree& tree, const Cloud& cloud, const std::vector<std::uint32_t>& pts,
                                         const Footprint& footprint, const InterferenceParams& params) {
  const std::vector<Eigen::Vector3f> normals = local_normals(tree, pts, params);
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (normals[i].squaredNorm() == 0 || footprint.on_stack[i]) continue;
    const Eigen::Vector3d ray = (cloud.points[pts[i]].cast<double>() - params.sensor_position).normalized();
    if (std::abs(ray.dot(normals[i].cast<double>())) >= params.veil_facing_cos) out.push_back(pts[i]);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// See InterferenceParams::veil_cos_max: most points' local surfaces contain their viewing rays. `footprint`: the
// cluster's pixels (image_footprint).
bool is_veil(const KdTree& tree, const Cloud& cloud, const std::vector<std::uint32_t>& pts, const Footprint& footprint,
             const InterferenceParams& params) {
  // Most pixels are stacks of points spread along their rays: depths between a foreground and a background, which
  // no surface gives (see InterferenceParams::stack_min_spread_mm).
  if (double(footprint.stacked) >= params.veil_fraction * double(footprint.pixels.size())) return true;
  const std::vector<Eigen::Vector2d>& pixels = footprint.pixels;
  const std::vector<Eigen::Vector3f> normals = local_normals(tree, pts, params);
  std::size_t grazing = 0, defined = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (normals[i].squaredNorm() == 0) continue;
    ++defined;
    const Eigen::Vector3d ray = (cloud.points[pts[i]].cast<double>() - params.sensor_position).normalized();
    if (std::abs(ray.dot(normals[i].cast<double>())) < params.veil_cos_max) ++grazing;
  }
  if (defined == 0 || double(grazing) < params.veil_fraction * double(defined)) return false;
  // ... and it is a curtain one or two pixels wide as the sensor sees it: its footprint across the mean viewing
  // ray is narrow where one looks at it. A real object seen obliquely (a box's flank) covers an area of the image.
  // The width is measured locally (within veil_local_radius_mm of a pixel, its median over the footprint): a curtain
  // along an edge that turns a corner, or along a curved edge, is narrow everywhere but not as a whole (campaign
  // seed 5151 scene_028: the veil under a plate's top edge and its end, an L in the image, 0.55 mm wide locally and
  // 4.3 mm as a whole, was reported as a foreign object over the cable; over its points rather than its pixels, a
  // 3.6 mm wide rod lying over a cable of scene_025 read 1.2 mm, its edges' mixed points outweighing its face).
  const double cell = std::max(params.veil_local_radius_mm, 6.0 * params.resolution_mm);
  const auto key = [cell](const Eigen::Vector2d& x) {
    return std::pair<long, long>(std::lround(std::floor(x.x() / cell)), std::lround(std::floor(x.y() / cell)));
  };
  std::map<std::pair<long, long>, std::vector<std::size_t>> grid;
  for (std::size_t k = 0; k < pixels.size(); ++k) grid[key(pixels[k])].push_back(k);
  std::vector<double> widths;
  const std::size_t stride = std::max<std::size_t>(1, pixels.size() / 256);
  for (std::size_t k = 0; k < pixels.size(); k += stride) {
    const auto [cx, cy] = key(pixels[k]);
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    Eigen::Matrix2d outer = Eigen::Matrix2d::Zero();
    std::size_t n = 0;
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy) {
        const auto it = grid.find({cx + dx, cy + dy});
        if (it == grid.end()) continue;
        for (std::size_t j : it->second) {
          const Eigen::Vector2d w = pixels[j] - pixels[k];
          if (w.norm() > cell) continue;
          sum += w;
          outer += w * w.transpose();
          ++n;
        }
      }
    if (n < 3) continue;
    const Eigen::Vector2d m = sum / double(n);
    const Eigen::Matrix2d cov = outer / double(n) - m * m.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
    widths.push_back(std::sqrt(12.0 * std::max(es.eigenvalues()(0), 0.0)));  // of a uniform strip
  }
  if (widths.empty()) return true;  // no pixel with neighbours: a scatter of rays, no surface
  const double width = median_in_place(widths);
  return width <= std::max(params.veil_max_width_mm, params.veil_max_width_res * params.resolution_mm);
}

// See InterferenceParams::float_*: most of the cluster's points float: the rays next to theirs hold almost nothing at
// their range, and not a surface on both sides of it, and the surface seen on the rays around theirs does not pass
// through them.
bool is_floating(const KdTree& tree, const Cloud& cloud, const std::vector<std::uint32_t>& pts,
                 const InterferenceParams& params) {
  if (params.float_min_same == 0 || pts.empty()) return false;
  const double res = std::max(params.resolution_mm, 1e-3);
  RayNeighbourParams rp;
  rp.lateral_mm = params.float_lateral_res * res;
  rp.tolerance_mm = params.float_range_tolerance_mm;
  rp.reach_mm = params.float_reach_mm;
  RaySurfaceParams sp;
  sp.lateral_mm = params.float_surface_lateral_res * res;
  sp.same_ray_mm = params.float_same_ray_res * res;
  sp.tolerance_mm = params.float_range_tolerance_mm;
  sp.reach_mm = params.float_reach_mm;
  sp.rays = params.float_rays;
  sp.min_inliers = params.float_min_inliers;
  const std::size_t stride = std::max<std::size_t>(1, pts.size() / std::max<std::size_t>(1, params.float_samples));
  std::size_t sampled = 0, floating = 0;
  std::vector<Neighbor> scratch;
  for (std::size_t k = 0; k < pts.size(); k += stride) {
    ++sampled;
    const Eigen::Vector3d x = cloud.points[pts[k]].cast<double>();
    const RayNeighbours n = ray_neighbours(tree, pts[k], x, params.sensor_position, rp, scratch);
    if (n.same >= params.float_min_same || std::min(n.front, n.behind) >= params.float_min_sides) continue;
    floating += params.float_rays == 0 || !seen_surface_at(tree, pts[k], x, params.sensor_position, sp, scratch).on;
  }
  return double(floating) >= params.float_fraction * double(sampled);
}

// A cluster lying over a bridged break (most of its points nearest a bridge segment) that is a tube of the cable's
// radius along the bridge's course is the cable's own untraced stretch: a run that ended short of a clamp leaves
// the cable between them to the bridge, whose guessed course the noisy surface leaves by more than the band.
bool is_own_untraced_stretch(const Cloud& cloud, const std::vector<std::uint32_t>& pts,
                             const std::vector<Cylinder>& chain, std::size_t measured_segments, double r,
                             const InterferenceParams& params) {
  std::vector<Eigen::Vector3d> xs;
  xs.reserve(pts.size());
  std::size_t on_bridge = 0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::uint32_t i : pts) {
    xs.push_back(cloud.points[i].cast<double>());
    mean += xs.back();
    on_bridge += distance_to_chain(chain, xs.back()).segment >= measured_segments;
  }
  if (2 * on_bridge <= pts.size()) return false;
  mean /= double(pts.size());
  const ChainPoint cp = distance_to_chain(chain, mean);
  const Cylinder& seg = chain[cp.segment];
  const Eigen::Vector3d dir = (seg.end - seg.start).normalized();
  const Eigen::Vector3d foot = seg.start + cp.t * (seg.end - seg.start);
  CylinderFitParams fp;
  fp.use_sensor = params.has_sensor;
  fp.sensor = params.sensor_position;
  fp.max_radius_mm = 3.0 * r;
  auto own = [&](const CylinderFitResult& f) {
    if (!f.ok || std::abs(f.radius_mm / r - 1.0) > params.own_stretch_radius_tolerance) return false;
    if (double(f.inliers) < params.own_stretch_min_inliers * double(xs.size())) return false;
    if (std::abs(f.axis.dot(dir)) < std::cos(params.own_stretch_max_angle_deg * M_PI / 180.0)) return false;
    // its axis within a radius of the bridge's course
    return distance_to_chain(chain, f.point).distance_mm <= r;
  };
  const CylinderFitResult f = fit_cylinder(xs, foot, dir, r, fp);
  if (own(f)) return true;
  // A sliver of the surface (the part beyond the band: a narrow arc) leaves the radius loose: its own surface then
  // fits a tube of the cable's radius as closely as any tube.
  CylinderFitParams fixed = fp;
  fixed.fix_radius = true;
  const CylinderFitResult g = fit_cylinder(xs, foot, dir, r, fixed);
  return f.ok && g.ok && g.rms_mm <= params.own_stretch_fixed_rms_factor * f.rms_mm && own(g);
}

}  // namespace

std::vector<Interference> find_interferences(const Cloud& cloud, const KdTree& tree, const Scene& scene,
                                             const SurfaceIndex& rigid, const std::vector<MeasuredCable>& cables,
                                             std::size_t which, const std::vector<int>& ignore_elements,
                                             const InterferenceParams& params) {
  return find_interferences(cloud, tree, scene, rigid, cables, which, ignore_elements, params, {});
}

std::vector<Interference> find_interferences(const Cloud& cloud, const KdTree& tree, const Scene& scene,
                                             const SurfaceIndex& rigid, const std::vector<MeasuredCable>& cables,
                                             std::size_t which, const std::vector<int>& ignore_elements,
                                             const InterferenceParams& params, const InterferenceContext& context) {
  std::vector<Interference> out;
  if (which >= cables.size()) return out;
  const MeasuredCable& me = cables[which];
  if (!me.found || me.chain.empty() || cloud.empty()) return out;
  const double r = me.radius_mm;
  const double reach = r + params.clearance_mm;
  // The measured model with its short breaks between runs bridged: what lies over the cable there is judged.
  // A break's stretch inside the cable's clamps and connectors (their boxes, a radius wider) is no unseen cable: the
  // runs end there by design (a 2.8 mm wire untraced for 42.6 mm through its clamp and under a box lying on it
  // beside the clamp: the box was missed).
  const auto held = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    double inside = 0;
    for (int e : ignore_elements) {
      // its rigid attached elements only (the cable's own box, or a harness it branches from, spans its whole course)
      if (e < 0 || e >= int(scene.elements.size()) || e == me.element || !rigid.contains(e)) continue;
      const Element& el = scene.elements[e];
      inside += segment_in_box_mm(a, b, el.bounds_min.array() - r, el.bounds_max.array() + r);
    }
    return std::min(inside, (b - a).norm());
  };
  const std::vector<Cylinder> chain = bridge_short_breaks(me.chain, bridge_limit_mm(params, r), held);
  // The gaps to the models (rigid CAD surfaces, other cables' chains) are measured over the breaks bridged without
  // that discount: a bridge through a clamp is a guess of the course, and taken against a bracket beside the clamp
  // it read a 0.60 mm gap at 0-0.20 mm (0.50-0.72 without it).
  const std::vector<Cylinder> model_chain = bridge_short_breaks(me.chain, bridge_limit_mm(params, r));
  const double graze = params.ray_graze_mm > 0 ? params.ray_graze_mm : std::max(params.resolution_mm, 1e-3);

  // 1. Candidates: P points within clearance of the fitted surface (one radius query per sub-cable), and
  //    with the sensor known, points a little farther that hide the cable from it.
  const double extra = params.has_sensor ? std::max(0.0, params.occlusion_extra_mm) : 0.0;
  const double query_reach = reach + extra;
  std::vector<std::uint8_t> seen(cloud.size(), 0);
  std::vector<std::uint8_t> occluding(cloud.size(), 0);
  std::vector<std::uint8_t> shadowing(cloud.size(), 0);  // beyond the clearance, its ray behind it within it
  const double shadow_reach = r + (params.shadow_within_clearance ? params.clearance_mm : 0.0);
  std::vector<std::uint32_t> candidates;
  std::vector<Neighbor> nb;
  for (const Cylinder& c : chain) {
    const Eigen::Vector3d mid = 0.5 * (c.start + c.end);
    tree.radius_unsorted(mid.cast<float>(), float(0.5 * c.length_mm() + query_reach + 1e-3), nb);
    for (const Neighbor& n : nb) {
      if (seen[n.index]) continue;
      seen[n.index] = 1;
      if (contains_sorted(me.points, n.index)) continue;  // S
      const Eigen::Vector3d p = cloud.points[n.index].cast<double>();
      const ChainPoint cp = distance_to_chain(chain, p);
      if (cp.beyond_end) continue;
      const double gap = cp.distance_mm - r;
      // over a bridged break the cable's course is a guess: its own untraced surface may lie a little off it
      const double band = cp.segment < me.chain.size()
                              ? params.own_surface_band_mm
                              : std::max(params.own_surface_band_mm, params.bridge_band_radii * r);
      if (gap < band || gap > params.clearance_mm + extra) continue;
      if (gap > params.clearance_mm) {
        // Beyond the clearance: only a point whose unseen body may come within it: its ray, continued behind it
        // (to the cable's far side), passes within shadow_reach of the cable's axis; it hides the cable when that
        // ray hits it.
        const Eigen::Vector3d u = (p - params.sensor_position).normalized();
        const Eigen::Vector3d q = p + u * (gap + 2.0 * r);
        double ray_axis = std::numeric_limits<double>::infinity();
        for (const Cylinder& s : chain) {
          ray_axis = std::min(ray_axis, segment_distance(p, q, s.start, s.end));
          if (ray_axis < r) break;
        }
        if (!(ray_axis < shadow_reach)) continue;
        occluding[n.index] = ray_axis < r ? 1 : 0;
        shadowing[n.index] = 1;
        candidates.push_back(n.index);
        continue;
      }
      if (params.has_sensor) {
        // Mixed pixels of any measured cable's silhouette (this one's, or one crossing over it).
        bool mixed = false;
        for (std::size_t k = 0; k < cables.size() && !mixed; ++k) {
          const MeasuredCable& mc = cables[k];
          if (!mc.found || mc.chain.empty()) continue;
          const double gap_k = k == which ? gap : distance_to_chain(mc.chain, p).distance_mm - mc.radius_mm;
          double ray_gap = std::numeric_limits<double>::infinity();
          for (const Cylinder& s : mc.chain)
            ray_gap = std::min(ray_gap, segment_distance(params.sensor_position, p, s.start, s.end) - mc.radius_mm);
          mixed = ray_gap < graze && ray_gap < gap_k - params.ray_graze_margin_mm;
        }
        if (mixed) continue;
      }
      candidates.push_back(n.index);
    }
  }
  // (No early return when there are no candidates: a cable touching a bracket hides the bracket's points under
  // it, and the checks on the models below need none.)
  std::sort(candidates.begin(), candidates.end());

  // 2. Labels.
  const auto label_of = [&](std::uint32_t idx) {
    const Eigen::Vector3d p = cloud.points[idx].cast<double>();
    double best = params.label_tolerance_mm;
    Label l;
    for (std::size_t k = 0; k < cables.size(); ++k) {
      if (k == which || !cables[k].found || cables[k].chain.empty()) continue;
      if (contains_sorted(cables[k].points, idx)) {
        l = {1, int(k)};
        best = 0;
        break;
      }
      const double d = std::abs(distance_to_chain(cables[k].chain, p).distance_mm - cables[k].radius_mm);
      if (d <= best) {
        best = d;
        l = {1, int(k)};
      }
    }
    if (best > 0) {
      const SurfacePoint s = rigid.closest(p, best);
      if (s.found() && s.distance_mm <= best) l = {0, s.element};
    }
    if (l.kind == 2 && context.cable_cad) {
      const SurfacePoint s = context.cable_cad->closest(p, params.cable_cad_tolerance_mm);
      if (s.found() && s.element != me.element) {
        l = {1, -1};  // another cable's stretch without a model: not an interference found by points
        for (std::size_t k = 0; k < cables.size(); ++k)
          if (cables[k].element == s.element) l.index = int(k);
      }
    }
    if (l.kind == 2 && context.hidden_by_rigid && context.hidden_by_rigid(p)) l = {3, -1};  // a mixed pixel
    return l;
  };
  std::vector<Label> labels(candidates.size());
  parallel_for_each_index(candidates.size(), [&](std::size_t i) { labels[i] = label_of(candidates[i]); }, 256);

  auto ignored = [&](int element) {
    return element >= 0 && std::find(ignore_elements.begin(), ignore_elements.end(), element) != ignore_elements.end();
  };
  std::map<Label, std::vector<std::uint32_t>> groups;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const Label& l = labels[i];
    // rigid elements and cables: from the models below; mixed pixels: never
    if (l.kind != 2) continue;
    groups[l].push_back(candidates[i]);
  }

  const double res = std::max(params.resolution_mm, 1e-3);
  const std::size_t min_size = std::max<std::size_t>(
      params.min_cluster_points, static_cast<std::size_t>(std::ceil(params.min_cluster_area_mm2 / (res * res))));

  // Cable to rigid element: the element's registered CAD surface against the measured chain (the facing
  // flanks are seen by no sensor, so a point gap reads wide: DESIGN "Measurement lessons"). The scan must show
  // the element there: at least a minimum cluster of points on its surface near the closest spot (a bracket
  // that is missing or moved is not an interference at its CAD place).
  Eigen::Vector3d chain_lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d chain_hi = -chain_lo;
  for (const Cylinder& c : model_chain) {
    chain_lo = chain_lo.cwiseMin(c.start).cwiseMin(c.end);
    chain_hi = chain_hi.cwiseMax(c.start).cwiseMax(c.end);
  }
  for (std::size_t e = 0; e < scene.elements.size(); ++e) {
    const Element& el = scene.elements[e];
    if (!rigid.contains(int(e)) || ignored(int(e)) || int(e) == me.element) continue;
    if ((el.bounds_min.array() > chain_hi.array() + reach).any() ||
        (el.bounds_max.array() < chain_lo.array() - reach).any())
      continue;
    const SurfaceIndex element_surface(scene, {int(e)});
    double gap = std::numeric_limits<double>::infinity();
    Interference f;
    for (const Cylinder& c : model_chain) {
      const double limit = std::min(reach, std::isfinite(gap) ? gap + r : reach);
      const SurfacePoint s = element_surface.closest_to_segment(c.start, c.end, params.surface_step_mm, limit);
      if (s.found() && s.distance_mm - r < gap) {
        gap = s.distance_mm - r;
        f.closest_on_other = s.point;
      }
    }
    if (!(gap < params.clearance_mm)) continue;
    // Support: scan points (not the cable's own) on this element's registered surface. The flank that faces
    // the cable is seen by no sensor, and a cable lying on a bracket hides the bracket around the contact, so
    // the points are looked for over the whole element; those nearest the closest spot are the entry's points.
    const double support_radius = std::max(params.support_radius_mm, 2.0 * r + params.clearance_mm);
    const Eigen::Vector3d el_centre = 0.5 * (el.bounds_min + el.bounds_max);
    const double el_reach = (f.closest_on_other - el_centre).norm() + 0.5 * (el.bounds_max - el.bounds_min).norm() +
                            params.label_tolerance_mm;
    tree.radius_unsorted(f.closest_on_other.cast<float>(), float(el_reach), nb);
    std::vector<std::pair<double, std::uint32_t>> on_surface;
    for (const Neighbor& n : nb) {
      if (contains_sorted(me.points, n.index)) continue;
      const Eigen::Vector3d p = cloud.points[n.index].cast<double>();
      if (((p - params.label_tolerance_mm * Eigen::Vector3d::Ones()).array() > el.bounds_max.array()).any() ||
          ((p + params.label_tolerance_mm * Eigen::Vector3d::Ones()).array() < el.bounds_min.array()).any())
        continue;
      const SurfacePoint s = element_surface.closest(p, params.label_tolerance_mm);
      if (!s.found()) continue;
      on_surface.emplace_back((p - f.closest_on_other).norm(), n.index);
    }
    if (on_surface.size() < min_size) continue;
    std::sort(on_surface.begin(), on_surface.end());
    const double keep_within = std::max(support_radius, on_surface[min_size - 1].first + 0.5 * support_radius);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const auto& [dist, index] : on_surface) {
      if (dist > keep_within) break;
      f.points.push_back(index);
      sum += cloud.points[index].cast<double>();
    }
    std::sort(f.points.begin(), f.points.end());
    f.center = sum / double(f.points.size());
    f.with = el.name;
    f.with_element = int(e);
    f.min_distance_mm = std::max(0.0, gap);
    const ChainPoint cp = distance_to_chain(model_chain, f.closest_on_other);
    const Cylinder& seg = model_chain[cp.segment];
    const Eigen::Vector3d axis_pt = seg.start + cp.t * (seg.end - seg.start);
    const Eigen::Vector3d d = f.closest_on_other - axis_pt;
    f.closest_on_cable = axis_pt + (d.norm() > 0 ? Eigen::Vector3d(d.normalized() * r) : Eigen::Vector3d::Zero());
    out.push_back(std::move(f));
  }

  // Cable to cable: both are measured models, so the gap is taken between the chains directly. A cable
  // crossing on top of this one shows only its far side to the sensor (no point within the clearance), so
  // points cannot decide this case; the other cable's points near the crossing count as its support.
  for (std::size_t k = 0; k < cables.size(); ++k) {
    const MeasuredCable& other = cables[k];
    if (k == which || !other.found || other.chain.empty()) continue;
    if (ignored(other.element) || (other.element >= 0 && other.element == me.element)) continue;
    // Both models with their short breaks bridged: a cable crossing over this one hides it from the sensor, so
    // the lower cable's trace often breaks exactly at the crossing (the gap would be read from the break's ends).
    const std::vector<Cylinder> other_chain =
        bridge_short_breaks(other.chain, bridge_limit_mm(params, other.radius_mm));
    Eigen::Vector3d pa, pb;
    const double axes = chain_distance(model_chain, other_chain, &pa, &pb);
    const double gap = axes - r - other.radius_mm;
    if (!(gap < params.clearance_mm)) continue;
    Interference f;
    const double near = r + params.clearance_mm + 2.0 * other.radius_mm;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (std::uint32_t i : other.points) {
      const Eigen::Vector3d p = cloud.points[i].cast<double>();
      if ((p - pa).norm() > near + other.radius_mm) continue;
      if (distance_to_chain(model_chain, p).distance_mm - r > params.clearance_mm + 2.0 * other.radius_mm) continue;
      f.points.push_back(i);
      sum += p;
    }
    if (f.points.empty()) continue;  // no scan support near the crossing
    f.center = sum / double(f.points.size());
    f.with = other.name;
    f.with_cable = int(k);
    f.with_element = other.element;
    f.min_distance_mm = std::max(0.0, gap);
    const Eigen::Vector3d dir = (pb - pa).norm() > 0 ? Eigen::Vector3d((pb - pa).normalized()) : Eigen::Vector3d::UnitX();
    f.closest_on_cable = pa + dir * r;
    f.closest_on_other = pb - dir * other.radius_mm;
    out.push_back(std::move(f));
  }

  const double tol = std::max(1.0, params.cluster_tolerance_factor * res);
  // The whole object a foreign cluster belongs to (see InterferenceParams::min_object_area_mm2): the cluster grown
  // (links within tol) over the cloud's points that lie on nothing known (a foreign candidate's label; not the
  // cable's points nor its own surface band) until it holds object_cap points. True when what it reached covers at
  // least object_min pixels (points, without the sensor: getting to the cap is enough then), or when it covers the
  // minimum cluster size and is at least min_object_length_mm long.
  const std::size_t object_min =
      std::max(min_size, static_cast<std::size_t>(std::ceil(params.min_object_area_mm2 / (res * res))));
  const std::size_t object_cap = 4 * object_min;
  std::vector<std::uint8_t> visited;  // all zero between calls
  // The cluster grown over such points until it holds `cap`.
  const auto grow_object = [&](const std::vector<std::uint32_t>& pts, std::size_t cap) {
    if (visited.empty()) visited.assign(cloud.size(), 0);
    std::vector<std::uint32_t> grown(pts.begin(), pts.end()), touched(pts.begin(), pts.end());
    for (std::uint32_t i : pts) visited[i] = 1;
    std::vector<Neighbor> around;
    for (std::size_t q = 0; q < grown.size() && grown.size() < cap; ++q) {
      tree.radius_unsorted(cloud.points[grown[q]], float(tol), around);
      for (const Neighbor& n : around) {
        if (visited[n.index]) continue;
        visited[n.index] = 1;
        touched.push_back(n.index);
        if (contains_sorted(me.points, n.index)) continue;
        const Eigen::Vector3d p = cloud.points[n.index].cast<double>();
        const ChainPoint cp = distance_to_chain(chain, p);
        if (!cp.beyond_end && cp.distance_mm - r < params.own_surface_band_mm) continue;
        // Past a run's end, the cable's own untraced continuation (into a connector or clamp) is no object's either:
        // within the band of the end segment's line (fresh campaign `--seed 2468 --campaign 40 --cables 3
        // --mismatch-patches 150 --outliers 0.45 --noise-mm 0.25`, scene_024: 20 points of a patch 1.7 mm over a
        // 13.6 mm cable grew over 176 points of the cable's last 6 mm before its connector into an object).
        if (cp.beyond_end) {
          const Cylinder& end = chain[cp.segment];
          const Eigen::Vector3d axis = (end.end - end.start).normalized(), v = p - end.start;
          if ((v - axis * axis.dot(v)).norm() - r < params.own_surface_band_mm) continue;
        }
        if (label_of(n.index).kind != 2) continue;
        grown.push_back(n.index);
      }
    }
    for (std::uint32_t i : touched) visited[i] = 0;
    return grown;
  };
  const auto whole_object_reaches = [&](const std::vector<std::uint32_t>& pts) {
    // Its size in pixels (points without the sensor), and its length: the widest spread of those pixels (points).
    // With the sensor, an object grown to the cap of points may still cover few pixels: stacks of mixed pixels hold
    // many points a pixel (fresh campaign `--seed 2468 --campaign 40 --cables 3 --mismatch-patches 150 --outliers
    // 0.45 --noise-mm 0.25`, scene_034: a mismatch patch and 10 stacks beside a clamp, 290 points on 34 pixels, 1 mm
    // over a cable, read as an object); it grows on (the cap doubled) until its pixels decide, up to
    // kObjectCapGrowth times the cap: an object of more points still is stacks (over 16 points a pixel), not an object.
    constexpr std::size_t kObjectCapGrowth = 4;
    std::vector<std::uint32_t> grown;
    std::vector<Eigen::Vector3d> spots;
    for (std::size_t cap = object_cap;; cap *= 2) {
      grown = grow_object(pts, cap);
      if (grown.size() >= cap && !params.has_sensor) return true;
      spots.clear();
      if (params.has_sensor) {
        for (const Eigen::Vector2d& px : image_footprint(cloud, grown, params).pixels)
          spots.emplace_back(px.x(), px.y(), 0.0);
      } else {
        for (std::uint32_t i : grown) spots.push_back(cloud.points[i].cast<double>());
      }
      if (params.has_sensor && params.pixel_pitch_rad > 0) {
        // the sensor's own pixels at the object's range (filter/pixel_pitch.hpp)
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (std::uint32_t i : grown) mean += cloud.points[i].cast<double>();
        const double pixel_mm = params.pixel_pitch_rad * (mean / double(grown.size()) - params.sensor_position).norm();
        if (spots.size() >= min_size && double(spots.size()) * pixel_mm * pixel_mm >= params.min_object_area_mm2)
          return true;
      } else if (spots.size() >= object_min) {
        return true;
      }
      if (grown.size() < cap) break;  // the whole object, and too few pixels
      if (cap >= kObjectCapGrowth * object_cap) return false;
    }
    if (spots.size() < min_size || !(params.min_object_length_mm > 0)) return false;
    const double length_sq = params.min_object_length_mm * params.min_object_length_mm;
    for (std::size_t a = 0; a < spots.size(); ++a)
      for (std::size_t b = a + 1; b < spots.size(); ++b)
        if ((spots[a] - spots[b]).squaredNorm() >= length_sq) return true;
    return false;
  };
  // The cable's own CAD samples that none of its runs traced (InterferenceParams::own_part_*), found when first needed.
  std::vector<Eigen::Vector3f> untraced;  // the tree may use them in place
  std::optional<KdTree> untraced_tree;
  const auto own_untraced_part = [&](const std::vector<std::uint32_t>& pts) {
    if (!context.cable_cad || !context.own_cad_samples || context.own_cad_samples->empty() || me.element < 0)
      return false;
    if (!untraced_tree) {
      for (const Eigen::Vector3d& s : *context.own_cad_samples)
        if (distance_to_chain(chain, s).distance_mm > context.own_cad_traced_within_mm) untraced.push_back(s.cast<float>());
      untraced_tree.emplace(untraced);
    }
    if (untraced_tree->size() == 0) return false;
    const std::vector<std::uint32_t> grown = grow_object(pts, std::max(params.own_part_max_points, pts.size()));
    const float reach = float(params.label_tolerance_mm + context.own_cad_spacing_mm);
    std::size_t on_own = 0, on_untraced = 0;
    for (std::uint32_t i : grown) {
      const Eigen::Vector3d p = cloud.points[i].cast<double>();
      on_untraced += untraced_tree->nearest(cloud.points[i], reach, ~0u).index != ~0u;
      const SurfacePoint s = context.cable_cad->closest(p, params.label_tolerance_mm);
      on_own += s.found() && s.element == me.element &&
                s.distance_mm + params.own_part_margin_mm < distance_to_chain(chain, p).distance_mm - r;
    }
    return on_untraced >= min_size && double(on_own) >= params.own_part_min_fraction * double(grown.size());
  };
  // 3. Foreign points: clustered; small clusters are noise, veils are mixed pixels.
  for (const auto& [label, subset] : groups) {
    if (subset.size() < min_size) continue;
    ClusterResult cr = euclidean_clusters(tree, subset, tol, min_size);
    const std::size_t first_clusters = cr.clusters.size();
    for (std::size_t ci = 0; ci < cr.clusters.size(); ++ci) {
      const std::vector<std::uint32_t> pts = cr.clusters[ci];  // a copy: the list may grow below
      if (params.has_sensor) {
        // Its size counted in pixels: many points on a few rays are noise too (see image_footprint).
        const Footprint footprint = image_footprint(cloud, pts, params);
        if (footprint.pixels.size() < min_size) continue;
        if (is_veil(tree, cloud, pts, footprint, params)) {
          // What in it faces the sensor, clustered again, is judged on its own (InterferenceParams::veil_facing_cos).
          if (ci < first_clusters && params.veil_facing_cos > 0) {
            const std::vector<std::uint32_t> facing = facing_points(tree, cloud, pts, footprint, params);
            if (facing.size() >= min_size) {
              ClusterResult parts = euclidean_clusters(tree, facing, tol, min_size);
              for (std::vector<std::uint32_t>& part : parts.clusters) cr.clusters.push_back(std::move(part));
            }
          }
          continue;
        }
        if (is_floating(tree, cloud, pts, params)) continue;  // wrong ranges about a surface, no surface of their own
      }
      if (chain.size() > me.chain.size() && is_own_untraced_stretch(cloud, pts, chain, me.chain.size(), r, params))
        continue;
      Interference f;
      f.points = pts;
      std::sort(f.points.begin(), f.points.end());
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (std::uint32_t i : f.points) sum += cloud.points[i].cast<double>();
      f.center = sum / double(f.points.size());
      double gap = std::numeric_limits<double>::infinity();
      for (std::uint32_t i : f.points) {
        const Eigen::Vector3d p = cloud.points[i].cast<double>();
        const ChainPoint cp = distance_to_chain(chain, p);
        if (cp.distance_mm - r < gap) {
          gap = cp.distance_mm - r;
          f.closest_on_other = p;
          const Cylinder& seg = chain[cp.segment];
          const Eigen::Vector3d axis_pt = seg.start + cp.t * (seg.end - seg.start);
          f.closest_on_cable = axis_pt + (p - axis_pt).normalized() * r;
        }
      }
      if (!std::isfinite(gap)) continue;
      f.min_distance_mm = std::max(0.0, gap);
      std::size_t shadows = 0;
      for (std::uint32_t i : f.points) {
        f.occluding_points += occluding[i];
        shadows += shadowing[i];
      }
      if (f.min_distance_mm >= params.clearance_mm && shadows < min_size) continue;
      if (object_min > min_size && !whole_object_reaches(f.points)) continue;
      if (own_untraced_part(f.points)) {
        if (context.untraced_parts) context.untraced_parts->push_back(f.center);
        continue;
      }
      out.push_back(std::move(f));
    }
  }
  std::sort(out.begin(), out.end(), [](const Interference& a, const Interference& b) {
    if (a.min_distance_mm != b.min_distance_mm) return a.min_distance_mm < b.min_distance_mm;
    return a.points.front() < b.points.front();
  });
  return out;
}

}  // namespace ewis
