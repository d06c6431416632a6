// Global registration: FPFH + RANSAC with edge-length pre-rejection, refined by ICP (see the header).
// Deterministic: hypothesis i draws from its own generator seeded by (seed, scale, i); hypotheses are scored in
// parallel into per-iteration slots and the best are chosen by (score, iteration index).
#include "ewis/register/global_registration.hpp"

#include <nanoflann.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "ewis/core/parallel.hpp"
#include "ewis/filter/voxel_grid.hpp"
#include "ewis/register/fpfh.hpp"
#include "ewis/register/point_normals.hpp"

namespace ewis {
namespace {

// splitmix64: a tiny generator whose state is the seed, so each hypothesis gets its own stream for free.
struct SplitMix {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  std::size_t below(std::size_t n) { return static_cast<std::size_t>(next() % n); }
};

// A voxel-down-sampled cloud with PCA normals, its tree and its FPFH features.
struct Prepared {
  Cloud cloud;
  std::unique_ptr<KdTree> tree;
  std::vector<Fpfh> features;
  std::vector<float> curvature;  // surface variation at the voxel scale
};

Prepared prepare(const Cloud& input, double voxel, const GlobalRegistrationParams& p,
                 const Eigen::Vector3d& viewpoint) {
  Prepared out;
  out.cloud = voxel_downsample(input, voxel).cloud;
  out.tree = std::make_unique<KdTree>(out.cloud.points);
  // PCA normals on both clouds, so that scan and CAD features are computed the same way; a cloud with
  // normals (CAD samples: outward triangle normals) orients them by those, otherwise toward its sensor.
  PointNormalParams np;
  np.k = p.normal_k;
  np.viewpoint = viewpoint;
  std::vector<Eigen::Vector3f> normals = estimate_point_normals(*out.tree, np, &out.curvature);
  if (out.cloud.normals.size() == normals.size()) {
    for (std::size_t i = 0; i < normals.size(); ++i)
      if (normals[i].dot(out.cloud.normals[i]) < 0) normals[i] = -normals[i];
  }
  out.cloud.normals = std::move(normals);
  FpfhParams fp;
  fp.radius_mm = p.feature_radius_factor * voxel;
  out.features = compute_fpfh(*out.tree, out.cloud.normals, fp);
  return out;
}

// nanoflann dataset over the 33-bin features.
struct FeatureAdaptor {
  const std::vector<Fpfh>* f;
  std::size_t kdtree_get_point_count() const { return f->size(); }
  float kdtree_get_pt(std::uint32_t i, std::size_t d) const { return (*f)[i][d]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const { return false; }
};
using FeatureTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, FeatureAdaptor, float, std::uint32_t>,
                                                        FeatureAdaptor, 33, std::uint32_t>;

bool all_zero(const Fpfh& f) {
  for (float v : f)
    if (v != 0.0f) return false;
  return true;
}

// For each usable source point: its k nearest target features (flattened, k per point).
struct Matches {
  std::vector<std::uint32_t> source;  // source indices with a feature
  std::vector<std::uint32_t> target;  // k per source entry
  int k = 1;
};

Matches match_features(const Prepared& src, const Prepared& tgt, int k) {
  Matches m;
  m.k = std::max(1, std::min<int>(k, static_cast<int>(tgt.features.size())));
  std::vector<std::uint32_t> usable_tgt;
  for (std::uint32_t i = 0; i < tgt.features.size(); ++i)
    if (!all_zero(tgt.features[i])) usable_tgt.push_back(i);
  if (usable_tgt.size() < 3) return m;
  std::vector<Fpfh> tf(usable_tgt.size());
  for (std::size_t i = 0; i < usable_tgt.size(); ++i) tf[i] = tgt.features[usable_tgt[i]];
  FeatureAdaptor adaptor{&tf};
  FeatureTree tree(33, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  for (std::uint32_t i = 0; i < src.features.size(); ++i)
    if (!all_zero(src.features[i])) m.source.push_back(i);
  m.k = std::min<int>(m.k, static_cast<int>(tf.size()));
  m.target.assign(m.source.size() * m.k, 0);
  parallel_blocks(m.source.size(), 128, [&](std::size_t b, std::size_t e) {
    std::vector<std::uint32_t> idx(m.k);
    std::vector<float> dist(m.k);
    for (std::size_t i = b; i < e; ++i) {
      const std::size_t found = tree.knnSearch(src.features[m.source[i]].data(), m.k, idx.data(), dist.data());
      for (int j = 0; j < m.k; ++j)
        m.target[i * m.k + j] = usable_tgt[idx[std::min<std::size_t>(j, found ? found - 1 : 0)]];
    }
  });
  return m;
}

Pose kabsch(const Eigen::Matrix3Xd& src, const Eigen::Matrix3Xd& dst) {
  Pose T = Pose::Identity();
  T.matrix() = Eigen::umeyama(src, dst, false);
  return T;
}

struct Hypothesis {
  int score = -1;  // probe inliers; -1: rejected
  Pose pose = Pose::Identity();
};

int count_within(const Prepared& tgt, const std::vector<Eigen::Vector3f>& pts, const std::vector<std::uint32_t>& idx,
                 std::size_t begin, std::size_t end, const Pose& T, double dist) {
  const float max_sq = static_cast<float>(dist * dist);
  int count = 0;
  for (std::size_t i = begin; i < end && i < idx.size(); ++i) {
    const Eigen::Vector3f p = (T * pts[idx[i]].cast<double>()).cast<float>();
    if (tgt.tree->nearest(p).distance_sq <= max_sq) ++count;
  }
  return count;
}

double rotation_between_deg(const Pose& a, const Pose& b) {
  const Eigen::AngleAxisd aa(a.linear().transpose() * b.linear());
  return std::abs(aa.angle()) * 180.0 / M_PI;
}

struct ScaleOutcome {
  RegistrationResult result;
  std::vector<RegistrationResult> candidates;
  std::size_t correspondences = 0;
  std::size_t scored = 0;
};

ScaleOutcome try_scale(const Cloud& source, const Cloud& target, double voxel, int scale_index,
                       const GlobalRegistrationParams& p) {
  ScaleOutcome out;
  const Prepared src = prepare(source, voxel, p, p.source_viewpoint);
  const Prepared tgt = prepare(target, voxel, p, p.target_viewpoint);
  if (src.cloud.size() < 3 || tgt.cloud.size() < 3) return out;
  const Matches m = match_features(src, tgt, p.correspondence_randomness);
  if (m.source.size() < 3) return out;
  out.correspondences = m.source.size() * m.k;

  // RANSAC samples come from the more curved points (edges, corners, round parts): on plates and walls every
  // point has the same feature, so their matches are random. Isolated points (outliers) are left out.
  std::vector<std::uint32_t> pool;  // entries of m.source
  {
    std::vector<std::pair<float, std::uint32_t>> ranked;
    for (std::uint32_t i = 0; i < m.source.size(); ++i) {
      const std::uint32_t si = m.source[i];
      if (src.tree->count_within(src.cloud.points[si], static_cast<float>(2.5 * voxel), 6) < 6) continue;
      ranked.emplace_back(src.curvature[si], i);
    }
    std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    const std::size_t keep = std::max<std::size_t>(
        std::min<std::size_t>(ranked.size(), 3),
        static_cast<std::size_t>(std::clamp(p.sample_fraction, 0.0, 1.0) * static_cast<double>(ranked.size())));
    for (std::size_t i = 0; i < keep; ++i) pool.push_back(ranked[i].second);
    std::sort(pool.begin(), pool.end());
  }
  if (pool.size() < 3) return out;

  // Probe points: evenly strided source points, for a cheap first score.
  std::vector<std::uint32_t> probe;
  const std::size_t np = std::min(std::max<std::size_t>(p.probe_points, 16), src.cloud.size());
  for (std::size_t i = 0; i < np; ++i) probe.push_back(static_cast<std::uint32_t>(i * src.cloud.size() / np));
  const double inlier_d = p.inlier_distance_factor * voxel;
  const double min_edge = p.min_edge_factor * voxel;
  const int tier1 = std::max(3, static_cast<int>(0.1 * std::min<std::size_t>(64, np)));

  const std::size_t iterations = static_cast<std::size_t>(std::max(1, p.max_iterations));
  std::vector<Hypothesis> hyp(iterations);
  parallel_blocks(iterations, 256, [&](std::size_t b, std::size_t e) {
    for (std::size_t it = b; it < e; ++it) {
      SplitMix rng{p.seed * 0x100000001B3ull ^ (static_cast<std::uint64_t>(scale_index) << 48) ^ it};
      rng.next();
      std::uint32_t s[3], t[3];
      for (int j = 0; j < 3; ++j) {
        const std::size_t pick = pool[rng.below(pool.size())];
        s[j] = m.source[pick];
        t[j] = m.target[pick * m.k + rng.below(m.k)];
      }
      if (s[0] == s[1] || s[0] == s[2] || s[1] == s[2] || t[0] == t[1] || t[0] == t[2] || t[1] == t[2]) continue;
      // Edge-length pre-rejection (a rigid motion keeps distances): cheap, and rejects most bad triples.
      bool ok = true;
      for (int a = 0; a < 3 && ok; ++a) {
        const int c = (a + 1) % 3;
        const double ds = (src.cloud.points[s[a]] - src.cloud.points[s[c]]).norm();
        const double dt = (tgt.cloud.points[t[a]] - tgt.cloud.points[t[c]]).norm();
        if (ds < min_edge || dt < min_edge || std::min(ds, dt) < p.edge_similarity * std::max(ds, dt)) ok = false;
      }
      if (!ok) continue;
      Eigen::Matrix3Xd S(3, 3), D(3, 3);
      for (int j = 0; j < 3; ++j) {
        S.col(j) = src.cloud.points[s[j]].cast<double>();
        D.col(j) = tgt.cloud.points[t[j]].cast<double>();
      }
      const Pose T = kabsch(S, D);
      if (!T.matrix().allFinite() || T.linear().determinant() < 0.5) continue;
      bool close = true;  // the three pairs themselves must land within the inlier distance
      for (int j = 0; j < 3; ++j) close = close && (T * S.col(j) - D.col(j)).norm() <= inlier_d;
      if (!close) continue;
      const std::size_t first = std::min<std::size_t>(64, probe.size());
      int score = count_within(tgt, src.cloud.points, probe, 0, first, T, inlier_d);
      if (score < tier1) {
        hyp[it].score = 0;
        hyp[it].pose = T;
        continue;
      }
      score += count_within(tgt, src.cloud.points, probe, first, probe.size(), T, inlier_d);
      hyp[it].score = score;
      hyp[it].pose = T;
    }
  });

  std::vector<std::uint32_t> order;
  for (std::uint32_t i = 0; i < hyp.size(); ++i)
    if (hyp[i].score > 0) order.push_back(i);
  out.scored = 0;
  for (const auto& h : hyp) out.scored += h.score >= 0;
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return hyp[a].score > hyp[b].score; });

  // The best distinct hypotheses, each refined by ICP on the down-sampled clouds; the highest fitness wins.
  std::vector<Pose> chosen;
  for (std::uint32_t i : order) {
    if (static_cast<int>(chosen.size()) >= std::max(1, p.candidates)) break;
    const Pose& T = hyp[i].pose;
    bool distinct = true;
    for (const Pose& c : chosen)
      if (rotation_between_deg(c, T) < 5.0 && (c.translation() - T.translation()).norm() < 2.0 * voxel) distinct = false;
    if (distinct) chosen.push_back(T);
  }
  bool have = false;
  for (const Pose& T0 : chosen) {
    IcpParams ip;
    ip.initial_max_distance_mm = 3.0 * inlier_d;
    ip.final_max_distance_mm = voxel;
    ip.noise_mm = 0.25 * voxel;
    ip.max_iterations_per_stage = 20;
    ip.max_iterations = 80;
    RegistrationResult r = align_point_to_plane(src.cloud.points, tgt.cloud, *tgt.tree, T0, ip);
    out.candidates.push_back(r);
    const bool better = !have || r.fitness > out.result.fitness + 1e-12 ||
                        (std::abs(r.fitness - out.result.fitness) <= 1e-12 && r.rmse_mm < out.result.rmse_mm);
    if (better) {
      out.result = r;
      have = true;
    }
  }
  std::stable_sort(out.candidates.begin(), out.candidates.end(),
                   [](const RegistrationResult& a, const RegistrationResult& b) { return a.fitness > b.fitness; });
  return out;
}

}  // namespace

GlobalRegistrationResult register_global(const Cloud& source, const Cloud& target,
                                         const GlobalRegistrationParams& params, const ProgressFn& progress) {
  GlobalRegistrationResult res;
  if (source.size() < 3 || target.size() < 3) return res;
  double voxel = params.voxel_mm;
  if (voxel <= 0) {
    // Sized by the part the clouds share: a scan holding a background larger than the CAD (a floor, the cell)
    // or a CAD larger than the view is measured by the other cloud.
    Eigen::Vector3f lo, hi;
    bounds(source.points, lo, hi);
    double diagonal = static_cast<double>((hi - lo).norm());
    if (params.voxel_from_smaller_cloud) {
      bounds(target.points, lo, hi);
      diagonal = std::min(diagonal, static_cast<double>((hi - lo).norm()));
    }
    voxel = std::max(1e-3, diagonal / std::max(1.0, params.voxel_div));
  }
  const std::vector<double> scales = params.scale_factors.empty() ? std::vector<double>{1.0} : params.scale_factors;
  bool have = false;
  for (std::size_t s = 0; s < scales.size(); ++s) {
    const double v = voxel * scales[s];
    ScaleOutcome o = try_scale(source, target, v, static_cast<int>(s), params);
    ++res.scales_tried;
    if (progress) progress("register-global", static_cast<double>(s + 1) / static_cast<double>(scales.size()));
    if (o.correspondences == 0) continue;
    if (params.try_all_scales) {
      res.candidates.insert(res.candidates.end(), o.candidates.begin(), o.candidates.end());
      o.candidates.clear();
    }
    if (!have || o.result.fitness > res.registration.fitness) {
      res.registration = o.result;
      res.voxel_mm = v;
      res.correspondences = o.correspondences;
      res.hypotheses_scored = o.scored;
      if (!params.try_all_scales) res.candidates = std::move(o.candidates);
      have = true;
    }
    if (res.registration.fitness >= params.min_fitness && !params.try_all_scales) break;
  }
  res.valid = have && res.registration.fitness >= params.min_fitness;
  return res;
}

}  // namespace ewis
