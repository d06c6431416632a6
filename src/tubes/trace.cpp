// paper 4.2: a tube as a chain of cylinders. Initialise (4.2.1), then move the search structure (4.2.2)
// both ways along the tube, one fitted sub-cable (4.2.3) after the other (4.2.4), bridging short gaps.
#include "ewis/tubes/trace.hpp"

#include <tbb/parallel_invoke.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "ewis/core/parallel.hpp"
#include "ewis/tubes/directions.hpp"
#include "tube_internal.hpp"

namespace ewis {
namespace tubes_detail {
// defined in chain.cpp
void finish_trace(Context& ctx, TubeTrace& trace);
}  // namespace tubes_detail

namespace {
using namespace tubes_detail;

struct Walk {
  std::vector<SubCable> segs;
  std::vector<TubeGap> gaps;
  std::string reason;
  double length = 0;
};

// Where a walk would have stopped on meeting the other half of the trace (see walk and meet_other): the step's end,
// the distance that counts as meeting, and the walk as it stood before the step.
struct MeetCheck {
  Eigen::Vector3d end;
  double near_mm;
  std::size_t segs, gaps;
  double length;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Sets the scale-dependent parameters once the starting cylinder is known.
void configure(Context& ctx, const AxisState& s) {
  const TubeParams& p = ctx.params;
  const double r = s.radius_mm, res = ctx.resolution_mm;
  const double shell = ctx.thin ? std::min(3.0 * s.rms_mm, r) : std::clamp(3.0 * s.rms_mm, 0.05 * r, 0.3 * r);
  ctx.tolerance_mm = p.surface_tolerance_mm > 0 ? p.surface_tolerance_mm : std::max(shell, 0.3 * res);
  // short steps tied to the radius follow bends (paper 4.2.4 "starts from where it stopped")
  ctx.step_mm = p.step_mm > 0 ? p.step_mm : std::max(r, 4.0 * res);
  ctx.expected_density = s.window_mm > 0 ? s.inliers / s.window_mm : 0.0;
  // The fit window holds at least kMinWindowPoints of the surface: a thin tube in a sparse scan has a few
  // points per mm, and a 20-point fit's radius wanders by more than the radius-jump limit.
  constexpr double kMinWindowPoints = 30.0;
  const double for_points = ctx.expected_density > 0 ? 0.5 * kMinWindowPoints / ctx.expected_density : 0.0;
  ctx.half_window_mm = std::max({0.75 * ctx.step_mm, 3.0 * res, std::min(for_points, 3.0 * ctx.step_mm)});
}

void init_directions(Context& ctx) {
  ctx.coarse = cone_directions(ctx.params.search_cone_deg, 6.0);
  ctx.fine1 = cone_directions(4.5, 1.5);
  ctx.fine2 = cone_directions(1.5, 0.5);
  ctx.bridge = cone_directions(8.0, 2.5);
}

// Near any segment of `segs` (skipping the last `skip_last`)?
bool near_chain(const std::vector<SubCable>& segs, std::size_t skip_last, const Eigen::Vector3d& p, double dist) {
  if (segs.size() <= skip_last) return false;
  for (std::size_t i = 0; i + skip_last < segs.size(); ++i)
    if (distance_to_segment(segs[i].cylinder, p) < dist) return true;
  return false;
}

// Where on [a, b] the stop region starts (bisection; a few stop_at calls, once at the last step).
Eigen::Vector3d stop_boundary(const TubeParams& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  double lo = 0, hi = 1;
  for (int i = 0; i < 8; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (p.stop_at(a + (b - a) * mid)) hi = mid; else lo = mid;
  }
  return a + (b - a) * lo;
}

SubCable make_seg(const Eigen::Vector3d& s, const Eigen::Vector3d& e, double r, std::uint32_t pts, double rms,
                  bool bridged) {
  SubCable c;
  c.cylinder.start = s;
  c.cylinder.end = e;
  c.cylinder.radius_mm = r;
  c.points = pts;
  c.rms_mm = rms;
  c.bridged = bridged;
  return c;
}

// paper 4.2.4: move the search structure along `dir` from the starting cylinder until the tube ends (or closes on
// itself). `meets` gets every place where the walk would stop on meeting the other half of the trace, in order, so
// that the test can be made once that half is known (meet_other): the walk itself does not depend on it.
Walk walk(Context& ctx, const AxisState& s, const Eigen::Vector3d& dir, std::vector<MeetCheck>* meets = nullptr) {
  Walk w;
  const TubeParams& p = ctx.params;
  Eigen::Vector3d a = s.point, d = dir.normalized();
  std::vector<double> radii{s.radius_mm}, arcs{s.arc_deg};
  double arc_ref = s.arc_deg;
  std::vector<double> rmss{s.rms_mm};
  double rms_ref = s.rms_mm;
  double r_ref = s.radius_mm;
  const double max_gap = p.max_gap_mm > 0 ? p.max_gap_mm : 6.0 * s.radius_mm;
  const double budget = 0.5 * p.max_length_mm;
  const long max_steps = std::min<long>(1000000, static_cast<long>(budget / ctx.step_mm) + 16);
  auto accept = [&](const StepResult& st) {
    w.segs.push_back(make_seg(st.start, st.end, st.radius_mm, st.points, st.rms_mm, false));
    w.length += (st.end - st.start).norm();
    a = st.end;
    d = st.dir;
    radii.push_back(st.radius_mm);
    // the reference radius follows slow changes (tapering branches), not single noisy fits
    std::vector<double> last(radii.end() - std::min<std::size_t>(radii.size(), 7), radii.end());
    r_ref = median(last);
    arcs.push_back(st.arc_deg);
    std::vector<double> last_arcs(arcs.end() - std::min<std::size_t>(arcs.size(), 7), arcs.end());
    arc_ref = median(last_arcs);
    rmss.push_back(st.rms_mm);
    std::vector<double> last_rms(rmss.end() - std::min<std::size_t>(rmss.size(), 7), rmss.end());
    rms_ref = median(last_rms);
  };
  w.reason = "step limit";
  for (long step = 0; step < max_steps; ++step) {
    if (w.length >= budget) {
      w.reason = "length limit";
      break;
    }
    StepResult st = propagate_step(ctx, a, d, r_ref, arc_ref, rms_ref, false);
    // trouble ahead that is not the end of the data: shorter steps get closer to it (paper 4.2.4: short
    // steps where the tube bends or meets something)
    for (double scale = 0.5; !st.ok && st.fail != "no data" && scale > 0.2; scale *= 0.5) {
      StepResult shorter = propagate_step(ctx, a, d, r_ref, arc_ref, rms_ref, false, scale);
      if (shorter.ok) st = shorter;
    }
    std::string fail;
    if (st.ok) {
      if (p.stop_at && p.stop_at(st.end)) {
        const Eigen::Vector3d b = stop_boundary(p, a, st.end);
        if ((b - a).norm() > 0.1 * ctx.step_mm) {
          st.end = b;
          accept(st);
        }
        w.reason = "stop region";
        break;
      }
      // a closed loop (a ring): stop instead of going round again; the other half of the trace is met afterwards
      const double near = 0.5 * r_ref;
      if (near_chain(w.segs, 3, st.end, near)) {
        w.reason = "loop";
        break;
      }
      if (meets) meets->push_back({st.end, near, w.segs.size(), w.gaps.size(), w.length});
      accept(st);
      if (!st.partial) continue;
      fail = "no data";
    } else {
      fail = st.fail;
    }
    // paper Fig. 11b: a hole (occlusion by a crossing cable, a clamp): extrapolate the direction and look
    // for the same tube further on; it must continue in line, with the same radius
    bool bridged = false, stopped = false;
    for (double g = 0.5 * ctx.step_mm; g <= max_gap + 1e-9; g += 0.5 * ctx.step_mm) {
      const Eigen::Vector3d as = a + d * g;
      if (p.stop_at && p.stop_at(as)) {
        stopped = true;
        break;
      }
      StepResult st2 = propagate_step(ctx, as, d, r_ref, arc_ref, rms_ref, true);
      if (!st2.ok || st2.partial) continue;
      const Eigen::Vector3d gend = st2.end + st2.dir * st2.dir.dot(as - st2.end);
      if ((gend - a).dot(d) <= 0) continue;
      w.segs.push_back(make_seg(a, gend, r_ref, 0, 0.0, true));
      w.gaps.push_back({a, gend});
      w.length += (gend - a).norm();
      st2.start = gend;
      accept(st2);
      bridged = true;
      break;
    }
    if (stopped) {
      w.reason = "stop region";
      break;
    }
    if (!bridged) {
      w.reason = fail;
      break;
    }
  }
  return w;
}

Context make_context(const Cloud& cloud, const KdTree& tree, const TubeParams& params, const Eigen::Vector3d& p0) {
  Context ctx(cloud, tree, params);
  ctx.resolution_mm = params.resolution_mm > 0 ? params.resolution_mm : local_resolution(tree, p0);
  ctx.thin = thin_tube(params, ctx.resolution_mm);
  init_directions(ctx);
  return ctx;
}

// The walk `w` as it would have ended had it been made with `other`: cut at the first place where it meets it.
void meet_other(Walk& w, const std::vector<MeetCheck>& meets, const std::vector<SubCable>& other) {
  for (const MeetCheck& m : meets)
    if (near_chain(other, 0, m.end, m.near_mm)) {
      w.segs.resize(m.segs);
      w.gaps.resize(m.gaps);
      w.length = m.length;
      w.reason = "loop";
      return;
    }
}

// Both walks from the starting cylinder, then the chain, centreline and points. The walks run at once: the backward
// one, which stops where it meets the forward one, is cut there afterwards (the same chain as one after the other;
// a ring's backward walk goes on round until it meets itself, work that is then dropped). Each has its own scratch
// and memo of normals (which only saves work); the backward one's memo is kept for what follows.
TubeTrace trace_from(Context& ctx, const AxisState& s, const Eigen::Vector3d& seed) {
  TubeTrace t;
  t.seed = seed;
  configure(ctx, s);
  auto memo = std::move(ctx.normals);
  ctx.normals.clear();
  Context back_ctx = ctx;
  ctx.normals = std::move(memo);
  Walk fwd, back;
  std::vector<MeetCheck> meets;
  tbb::parallel_invoke([&] { fwd = walk(ctx, s, s.dir); }, [&] { back = walk(back_ctx, s, -s.dir, &meets); });
  meet_other(back, meets, fwd.segs);
  ctx.normals.merge(back_ctx.normals);
  for (auto it = back.segs.rbegin(); it != back.segs.rend(); ++it) {
    SubCable c = *it;
    std::swap(c.cylinder.start, c.cylinder.end);
    t.segments.push_back(c);
  }
  for (auto it = back.gaps.rbegin(); it != back.gaps.rend(); ++it) t.gaps.push_back({it->end, it->start});
  t.segments.insert(t.segments.end(), fwd.segs.begin(), fwd.segs.end());
  t.gaps.insert(t.gaps.end(), fwd.gaps.begin(), fwd.gaps.end());
  t.end_reason_front = back.reason;
  t.end_reason_back = fwd.reason;
  if (t.segments.empty()) {
    // a tube shorter than one step: the starting cylinder is the whole chain
    const double hl = 0.5 * s.window_mm;
    t.segments.push_back(make_seg(s.point - s.dir * hl, s.point + s.dir * hl, s.radius_mm, s.inliers, s.rms_mm, false));
  }
  t.found = true;
  finish_trace(ctx, t);
  return t;
}

}  // namespace

TubeTrace trace_tube(const Cloud& cloud, const KdTree& tree, const Eigen::Vector3d& seed, const TubeParams& params) {
  TubeTrace none;
  none.seed = seed;
  if (cloud.empty() || tree.size() == 0 || !seed.allFinite()) return none;
  std::vector<Neighbor> nb;
  tree.knn(seed.cast<float>(), 128, nb);
  std::vector<std::uint32_t> cands;
  for (const Neighbor& n : nb) {
    if (params.usable && (n.index >= params.usable->size() || !(*params.usable)[n.index])) continue;
    cands.push_back(n.index);
  }
  if (cands.empty()) return none;
  Context ctx = make_context(cloud, tree, params, cloud.points[cands.front()].cast<double>());
  // the nearest surface point first; a few farther ones in case it was an outlier
  const std::size_t picks[] = {0, 8, 32, 96};
  for (std::size_t k : picks) {
    if (k >= cands.size()) break;
    AxisState s;
    if (initialise_at(ctx, cloud.points[cands[k]].cast<double>(), params.radius_mm, s)) return trace_from(ctx, s, seed);
  }
  return none;
}

constexpr int kMaxStartAttempts = 24;          // starts tried per pass
constexpr std::size_t kSecondPassCandidates = 400;  // CAD points ranked in the second pass (evenly strided)
constexpr double kSecondPassMinLengthRadii = 8.0;   // its traces are at least 4 diameters long

TubeTrace trace_cable(const Cloud& cloud, const KdTree& tree, const std::vector<Eigen::Vector3d>& cad_points,
                      double radius_mm, const TubeParams& params_in) {
  TubeTrace none;
  if (!cad_points.empty()) none.seed = cad_points.front();
  if (cloud.empty() || tree.size() == 0 || cad_points.empty() || !(radius_mm > 0)) return none;
  TubeParams params = params_in;
  params.radius_mm = radius_mm;
  // paper 4.2.1: a sphere of the cable radius around each CAD point; count scan points; sort. Around a thin tube's
  // axis (TubeParams::thin_max_px) that sphere holds only the points whose noise took them inside it, a few at most
  // (a 2.2 mm wire at 0.5 mm spacing: under the 10 a start needs): its sphere reaches 2 resolutions beyond.
  const std::size_t n = cad_points.size();
  std::vector<std::uint32_t> counts(n, 0);
  const double sphere_mm = thin_tube(params, params.resolution_mm) ? radius_mm + 2.0 * params.resolution_mm : radius_mm;
  const float rf = static_cast<float>(sphere_mm);
  parallel_for_each_index(n, [&](std::size_t i) {
    if (cad_points[i].allFinite())
      counts[i] = static_cast<std::uint32_t>(tree.count_within(cad_points[i].cast<float>(), rf, 1u << 30));
  }, 64);
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return counts[a] > counts[b]; });
  Context ctx = make_context(cloud, tree, params, cad_points[order.front()]);
  std::vector<Eigen::Vector3d> failed;
  std::vector<Neighbor> inside;
  int attempts = 0;
  // One start around CAD point c: paper Fig. 8d, step 1: spheres re-centred on the (usable) points within
  // `reach` of c; step 2: the fullest (most points within the radius) is the start.
  // `min_length_mm`: shorter traces are no cable (the second pass, searching wide, must find a stretch: a
  // few mm grown from stray points beside a clamp or bracket are what a wide search picks up otherwise).
  auto attempt = [&](const Eigen::Vector3d& c, double reach, double min_length_mm, TubeTrace& out) {
    ++attempts;
    tree.radius(c.cast<float>(), static_cast<float>(reach), inside);
    std::sort(inside.begin(), inside.end(), [](const Neighbor& a, const Neighbor& b) { return a.index < b.index; });
    // at most ~200 re-centred spheres (the second pass's wide search strides over its usable points only)
    if (reach > radius_mm)
      inside.erase(std::remove_if(inside.begin(), inside.end(), [&](const Neighbor& nb) { return !ctx.usable(nb.index); }),
                   inside.end());
    if (inside.empty()) {
      failed.push_back(c);
      return false;
    }
    const std::size_t stride = std::max<std::size_t>(1, inside.size() / 200);
    std::uint32_t best = inside.front().index;
    std::size_t best_count = 0;
    for (std::size_t k = 0; k < inside.size(); k += stride) {
      if (!ctx.usable(inside[k].index)) continue;
      const std::size_t cnt = tree.count_within(cloud.points[inside[k].index], rf, 1u << 30);
      if (cnt > best_count) {
        best_count = cnt;
        best = inside[k].index;
      }
    }
    AxisState s;
    if (initialise_at(ctx, cloud.points[best].cast<double>(), radius_mm, s) &&
        std::abs(s.radius_mm / radius_mm - 1.0) <= 0.35) {
      // A start beside a clamp or connector can grow one odd sub-cable and stop at once: that is no cable
      // (shorter than a diameter, or of another radius); the next candidate is tried (paper 4.2.1's fallback).
      TubeTrace t = trace_from(ctx, s, c);
      if (t.found && t.length_mm >= min_length_mm && std::abs(t.radius_mm / radius_mm - 1.0) <= 0.35) {
        out = std::move(t);
        return true;
      }
    }
    failed.push_back(c);
    return false;
  };
  TubeTrace found;
  for (std::uint32_t ci : order) {
    if (counts[ci] < 10 || attempts >= kMaxStartAttempts) break;
    const Eigen::Vector3d& c = cad_points[ci];
    // a failed candidate's neighbours would fail the same way: skip them
    if (std::any_of(failed.begin(), failed.end(), [&](const Eigen::Vector3d& f) { return (f - c).norm() < radius_mm; }))
      continue;
    if (attempt(c, sphere_mm, 2.0 * radius_mm, found)) return found;
  }
  // Second pass, when the cable lies off its CAD by more than its radius (a displaced cable: the spheres
  // around the CAD points hold none of it) wherever the first pass could start: candidates ranked by the
  // usable points within seed_search_mm, each searched that far.
  const double reach = params.seed_search_mm;
  if (!(reach > radius_mm)) return none;
  const std::size_t stride2 = std::max<std::size_t>(1, n / kSecondPassCandidates);
  std::vector<std::uint32_t> cand2;
  for (std::size_t i = 0; i < n; i += stride2)
    if (cad_points[i].allFinite()) cand2.push_back(static_cast<std::uint32_t>(i));
  std::vector<std::uint32_t> usable_near(n, 0);
  parallel_for_each_index(cand2.size(), [&](std::size_t k) {
    std::vector<Neighbor> nb;
    tree.radius(cad_points[cand2[k]].cast<float>(), static_cast<float>(reach), nb);
    std::uint32_t u = 0;
    for (const Neighbor& q : nb) u += ctx.usable(q.index);
    usable_near[cand2[k]] = u;
  }, 8);
  std::stable_sort(cand2.begin(), cand2.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return usable_near[a] > usable_near[b]; });
  int attempts2 = 0;
  for (std::uint32_t ci : cand2) {
    if (usable_near[ci] < 10 || attempts2 >= kMaxStartAttempts) break;
    const Eigen::Vector3d& c = cad_points[ci];
    if (std::any_of(failed.begin(), failed.end(), [&](const Eigen::Vector3d& f) { return (f - c).norm() < 0.5 * reach; }))
      continue;
    ++attempts2;
    if (attempt(c, reach, kSecondPassMinLengthRadii * radius_mm, found)) return found;
  }
  return none;
}

}  // namespace ewis
