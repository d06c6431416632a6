// Two runs of one cable joined across the gap between their ends (see run_joins.hpp).
#include "ewis/inspect/run_joins.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "ewis/core/cylinder.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis {
namespace {

// One end of a run: its last centreline point, the outward direction over its last stretch, and the run's
// centreline samples from that end inwards up to `keep_mm` of arc (nearest the end first).
struct RunEnd {
  bool ok = false;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d outward = Eigen::Vector3d::Zero();
  std::vector<std::size_t> part;  // centreline indices, from the end inwards
};

RunEnd run_end(const TubeTrace& run, bool back, double direction_mm, double keep_mm) {
  RunEnd e;
  const std::vector<Eigen::Vector3d>& c = run.centerline;
  if (c.size() < 3) return e;
  const std::string& reason = back ? run.end_reason_back : run.end_reason_front;
  if (reason == "stop region" || reason == "loop") return e;
  const auto at = [&](std::size_t j) { return back ? c.size() - 1 - j : j; };
  double arc = 0.0;
  std::vector<std::size_t> stretch;  // the last direction_mm
  for (std::size_t j = 0; j < c.size(); ++j) {
    if (j > 0) arc += (c[at(j)] - c[at(j - 1)]).norm();
    if (arc > keep_mm) break;
    e.part.push_back(at(j));
    if (arc <= direction_mm) stretch.push_back(at(j));
  }
  if (stretch.size() < 2) return e;
  // The stretch's principal direction, pointing out of the run.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t i : stretch) mean += c[i];
  mean /= double(stretch.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::size_t i : stretch) cov += (c[i] - mean) * (c[i] - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Eigen::Vector3d d = eig.eigenvectors().col(2);
  if (d.dot(c[stretch.front()] - c[stretch.back()]) < 0) d = -d;
  e.point = c[at(0)];
  e.outward = d;
  e.ok = d.allFinite();
  return e;
}

double point_segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return distance_to_segment(Cylinder{a, b, 0.0}, p);
}

// Run ends joinable at all (see run_end), and for each pair (k, bk, l, bl) whether a third run's end lies at the
// gap between them (RunJoinParams::fork_*).
struct Ends {
  std::vector<std::array<RunEnd, 2>> ends;
  double fork_reach = 0.0;
  bool third_at_gap(std::size_t k, int bk, std::size_t l, int bl) const {
    const RunEnd &a = ends[k][bk], &b = ends[l][bl];
    for (std::size_t m = 0; m < ends.size(); ++m) {
      if (m == k || m == l) continue;
      for (int bm = 0; bm < 2; ++bm)
        if (ends[m][bm].ok && point_segment_distance(ends[m][bm].point, a.point, b.point) <= fork_reach) return true;
    }
    return false;
  }
};

Ends run_ends(const std::vector<TubeTrace>& runs, double diameter_mm, const RunJoinParams& params) {
  Ends e;
  const double keep = params.keep_diameters * diameter_mm, direction = params.end_direction_diameters * diameter_mm;
  e.ends.resize(runs.size());
  for (std::size_t k = 0; k < runs.size(); ++k)
    for (int b = 0; b < 2; ++b) e.ends[k][b] = run_end(runs[k], b == 1, direction, keep);
  e.fork_reach = std::max(params.fork_reach_diameters * diameter_mm, params.fork_reach_min_mm);
  return e;
}

}  // namespace

std::vector<Eigen::Vector3d> run_forks(const std::vector<TubeTrace>& runs, double diameter_mm,
                                       const RunJoinParams& params) {
  std::vector<Eigen::Vector3d> forks;
  if (runs.size() < 2 || !(diameter_mm > 0)) return forks;
  const Ends e = run_ends(runs, diameter_mm, params);
  const double max_gap = std::max(params.max_gap_diameters * diameter_mm, params.min_gap_mm);
  // A fork already found within the gap limit of another's place is not found again.
  const auto add = [&](const Eigen::Vector3d& place) {
    if (std::none_of(forks.begin(), forks.end(), [&](const Eigen::Vector3d& f) { return (f - place).norm() <= max_gap; }))
      forks.push_back(place);
  };
  // Three ends of three runs together (a trunk split at the fork, and the branch): their mean.
  for (std::size_t k = 0; k < runs.size(); ++k)
    for (std::size_t l = k + 1; l < runs.size(); ++l)
      for (int bk = 0; bk < 2; ++bk)
        for (int bl = 0; bl < 2; ++bl) {
          const RunEnd &a = e.ends[k][bk], &b = e.ends[l][bl];
          if (!a.ok || !b.ok || (b.point - a.point).norm() > max_gap) continue;
          for (std::size_t m = 0; m < runs.size(); ++m)
            for (int bm = 0; bm < 2; ++bm) {
              const RunEnd& c = e.ends[m][bm];
              if (m == k || m == l || !c.ok || point_segment_distance(c.point, a.point, b.point) > e.fork_reach) continue;
              add((a.point + b.point + c.point) / 3.0);
            }
        }
  // A run ending inside another's tube, away from that run's ends: a branch traced up to the trunk it leaves (the
  // trunk traced through the fork). Its place is the nearest point on the other run's centreline.
  for (std::size_t l = 0; l < runs.size(); ++l)
    for (int bl = 0; bl < 2; ++bl) {
      const RunEnd& a = e.ends[l][bl];
      if (!a.ok) continue;
      for (std::size_t k = 0; k < runs.size(); ++k) {
        const std::vector<Eigen::Vector3d>& c = runs[k].centerline;
        if (k == l || c.size() < 2) continue;
        double best = std::numeric_limits<double>::infinity(), at_arc = 0.0, arc = 0.0;
        Eigen::Vector3d nearest = c.front();
        for (std::size_t i = 0; i + 1 < c.size(); ++i) {
          const Eigen::Vector3d ab = c[i + 1] - c[i];
          const double len = ab.norm();
          const double t = len > 0 ? std::clamp((a.point - c[i]).dot(ab) / (len * len), 0.0, 1.0) : 0.0;
          const Eigen::Vector3d q = c[i] + t * ab;
          if ((q - a.point).norm() < best) {
            best = (q - a.point).norm();
            nearest = q;
            at_arc = arc + t * len;
          }
          arc += len;
        }
        if (best <= runs[k].radius_mm && at_arc >= diameter_mm && arc - at_arc >= diameter_mm) add(nearest);
      }
    }
  return forks;
}

std::vector<RunJoin> join_runs_across_gaps(const std::vector<TubeTrace>& runs, const std::vector<Eigen::Vector3f>& cloud,
                                           double diameter_mm, const RunJoinParams& params) {
  std::vector<RunJoin> joins;
  if (!params.enabled || runs.size() < 2 || !(diameter_mm > 0)) return joins;
  const double max_gap = std::max(params.max_gap_diameters * diameter_mm, params.min_gap_mm);
  const double min_cos_turn = std::cos(params.min_turn_deg * M_PI / 180.0);
  const Ends all = run_ends(runs, diameter_mm, params);
  const std::vector<std::array<RunEnd, 2>>& ends = all.ends;
  for (std::size_t k = 0; k < runs.size(); ++k)
    for (std::size_t l = k + 1; l < runs.size(); ++l)
      for (int bk = 0; bk < 2; ++bk)
        for (int bl = 0; bl < 2; ++bl) {
          const RunEnd &a = ends[k][bk], &b = ends[l][bl];
          if (!a.ok || !b.ok) continue;
          const Eigen::Vector3d gap = b.point - a.point;
          const double g = gap.norm();
          if (g > max_gap) continue;
          // Going on straight (the outward directions opposite): no bend hidden. Each end's line must run towards
          // the other end (a bend's legs meet ahead of both ends).
          if (-a.outward.dot(b.outward) > min_cos_turn) continue;
          if (g > 0 && (a.outward.dot(gap) <= 0 || b.outward.dot(-gap) <= 0)) continue;
          // The legs' lines meet (within max_miss_diameters) ahead of both ends, no farther than the gap limit: a
          // corner, not two stretches side by side (a hairpin's legs, whose ends may lie near each other).
          {
            const Eigen::Vector3d w0 = a.point - b.point;
            const double c = a.outward.dot(b.outward), den = 1.0 - c * c;
            const double ta = (c * b.outward.dot(w0) - a.outward.dot(w0)) / den,
                         tb = (b.outward.dot(w0) - c * a.outward.dot(w0)) / den;
            const double miss = ((a.point + ta * a.outward) - (b.point + tb * b.outward)).norm();
            if (!(miss <= params.max_miss_diameters * diameter_mm) || ta < -diameter_mm || tb < -diameter_mm ||
                ta > max_gap || tb > max_gap)
              continue;
          }
          if (all.third_at_gap(k, bk, l, bl)) continue;  // a fork
          RunJoin j;
          j.first = k;
          j.second = l;
          j.gap_start = a.point;
          j.gap_end = b.point;
          // a's part from inside out, the gap at the centreline's spacing (at most a radius), b's part from its end in.
          const TubeTrace &ra = runs[k], &rb = runs[l];
          for (auto it = a.part.rbegin(); it != a.part.rend(); ++it) j.centerline.push_back(ra.centerline[*it]);
          const double step = std::max(0.25, 0.5 * std::min(ra.radius_mm, rb.radius_mm));
          const int n = int(std::ceil(g / step));
          for (int i = 1; i < n; ++i) j.centerline.push_back(a.point + gap * (double(i) / n));
          for (std::size_t i : b.part) j.centerline.push_back(rb.centerline[i]);
          // Each run's points whose nearest centreline sample of that run lies in its kept part.
          for (const auto& [run, end] : {std::pair{&ra, &a}, std::pair{&rb, &b}}) {
            std::vector<Eigen::Vector3f> cl(run->centerline.size());
            for (std::size_t i = 0; i < cl.size(); ++i) cl[i] = run->centerline[i].cast<float>();
            std::vector<std::uint8_t> kept(cl.size(), 0);
            for (std::size_t i : end->part) kept[i] = 1;
            const KdTree tree(cl);
            for (std::uint32_t i : run->points) {
              const Neighbor nb = tree.nearest(cloud[i]);
              if (nb.index != UINT32_MAX && kept[nb.index]) j.points.push_back(i);
            }
          }
          std::sort(j.points.begin(), j.points.end());
          j.points.erase(std::unique(j.points.begin(), j.points.end()), j.points.end());
          const double wa = double(std::max<std::size_t>(1, ra.points.size())),
                       wb = double(std::max<std::size_t>(1, rb.points.size()));
          j.radius_mm = (ra.radius_mm * wa + rb.radius_mm * wb) / (wa + wb);
          joins.push_back(std::move(j));
        }
  return joins;
}

std::vector<std::uint32_t> points_under_something(const RunJoin& join, const std::vector<Eigen::Vector3f>& cloud,
                                                  const KdTree& tree, const std::vector<std::uint8_t>* usable,
                                                  const Eigen::Vector3d& sensor, double diameter_mm,
                                                  const RunJoinParams& params) {
  std::vector<std::uint32_t> under;
  const Eigen::Vector3d centre = 0.5 * (join.gap_start + join.gap_end);
  const double reach = 0.5 * (join.gap_end - join.gap_start).norm() + params.edge_reach_diameters * diameter_mm;
  std::vector<Neighbor> near;
  tree.radius_unsorted(centre.cast<float>(), float(reach), near);  // the answer is sorted at the end
  const double step = params.front_ray_mm;
  for (const Neighbor& nb : near) {
    if (usable && !(*usable)[nb.index]) continue;
    const Eigen::Vector3d x = cloud[nb.index].cast<double>();
    const Eigen::Vector3d ray = sensor - x;
    const double far = std::min(params.front_max_mm, ray.norm());
    const Eigen::Vector3d u = ray.normalized();
    for (double t = params.front_min_mm; t <= far; t += step)
      if (tree.count_within((x + t * u).cast<float>(), float(params.front_ray_mm), 1) > 0) {
        under.push_back(nb.index);
        break;
      }
  }
  std::sort(under.begin(), under.end());
  return under;
}

}  // namespace ewis
