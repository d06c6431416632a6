// KdTree against brute force on random clouds with ties and duplicates.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "ewis/search/kdtree.hpp"
#include "ewis/search/moving_nearest.hpp"
#include "ewis/search/spatial_sort.hpp"

using namespace ewis;

namespace {

// The same float arithmetic as nanoflann's L2_Simple_Adaptor, so distances compare bit for bit.
float dist_sq(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
  float d = 0;
  for (int i = 0; i < 3; ++i) {
    const float t = a[i] - b[i];
    d += t * t;
  }
  return d;
}

bool finite(const Eigen::Vector3f& p) { return p.allFinite(); }

std::vector<Neighbor> brute_sorted(const std::vector<Eigen::Vector3f>& pts, const Eigen::Vector3f& q) {
  std::vector<Neighbor> all;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (finite(pts[i])) all.push_back({static_cast<std::uint32_t>(i), dist_sq(q, pts[i])});
  std::sort(all.begin(), all.end(), [](const Neighbor& a, const Neighbor& b) {
    return a.distance_sq < b.distance_sq || (a.distance_sq == b.distance_sq && a.index < b.index);
  });
  return all;
}

// Integer coordinates in a small box: many exactly equal distances; plus exact duplicates.
std::vector<Eigen::Vector3f> tie_cloud(std::uint32_t seed, std::size_t n) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> c(-6, 6);
  std::vector<Eigen::Vector3f> pts;
  for (std::size_t i = 0; i < n; ++i) pts.emplace_back(float(c(rng)), float(c(rng)), float(c(rng)) * 0.5f);
  for (std::size_t i = 0; i < n / 10; ++i) pts.push_back(pts[i * 3]);
  return pts;
}

std::vector<Eigen::Vector3f> random_cloud(std::uint32_t seed, std::size_t n) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-50.f, 50.f);
  std::vector<Eigen::Vector3f> pts;
  for (std::size_t i = 0; i < n; ++i) pts.emplace_back(u(rng), u(rng), u(rng));
  return pts;
}

std::vector<Eigen::Vector3f> queries(std::uint32_t seed, std::size_t n, float extent) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-extent, extent);
  std::uniform_int_distribution<int> c(-7, 7);
  std::vector<Eigen::Vector3f> q;
  for (std::size_t i = 0; i < n; ++i) {
    q.emplace_back(u(rng), u(rng), u(rng));
    q.emplace_back(float(c(rng)), float(c(rng)), float(c(rng)) * 0.5f);  // on the lattice: ties
  }
  return q;
}

void expect_same(const std::vector<Neighbor>& a, const std::vector<Neighbor>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].index, b[i].index) << "rank " << i;
    EXPECT_EQ(a[i].distance_sq, b[i].distance_sq) << "rank " << i;
  }
}

}  // namespace

class KdTreeBrute : public ::testing::TestWithParam<int> {};

TEST_P(KdTreeBrute, KnnRadiusCountNearestMatchBruteForce) {
  const bool ties = GetParam() == 0;
  const auto pts = ties ? tie_cloud(7, 1500) : random_cloud(11, 3000);
  const KdTree tree(pts);
  ASSERT_EQ(tree.size(), pts.size());
  std::vector<Neighbor> got;
  for (const auto& q : queries(3, 60, ties ? 7.f : 55.f)) {
    const auto all = brute_sorted(pts, q);
    for (int k : {1, 2, 7, 16, 40}) {
      tree.knn(q, k, got);
      expect_same(got, std::vector<Neighbor>(all.begin(), all.begin() + k));
    }
    const Neighbor nn = tree.nearest(q);
    EXPECT_EQ(nn.index, all[0].index);
    EXPECT_EQ(nn.distance_sq, all[0].distance_sq);
    // Bounded and hinted: the same answer within the bound (ties still by index: on the lattice the hint is
    // often a tied point of a larger index), none beyond it, whatever the hint.
    for (float r : {0.0f, 1.0f, 2.0f, 7.5f, 1e4f})
      for (std::uint32_t hint : {std::numeric_limits<std::uint32_t>::max(), all[0].index, all[1].index,
                                 all[all.size() / 2].index, all.back().index, std::uint32_t(pts.size() + 5)}) {
        const Neighbor b = tree.nearest(q, r, hint);
        if (all[0].distance_sq <= r * r) {
          EXPECT_EQ(b.index, all[0].index) << "r " << r << " hint " << hint;
          EXPECT_EQ(b.distance_sq, all[0].distance_sq);
        } else {
          EXPECT_EQ(b.index, std::numeric_limits<std::uint32_t>::max()) << "r " << r << " hint " << hint;
        }
      }
    for (float r : {0.0f, 1.0f, 1.5f, 2.0f, 7.5f}) {
      std::vector<Neighbor> want;
      for (const auto& nb : all)
        if (nb.distance_sq <= r * r) want.push_back(nb);
      tree.radius(q, r, got);
      expect_same(got, want);  // inclusive: lattice points at exactly r are in
      tree.radius_unsorted(q, r, got);
      EXPECT_EQ(got.size(), want.size());
      EXPECT_EQ(tree.count_within(q, r, std::numeric_limits<std::size_t>::max()), want.size());
      for (std::size_t stop : {1u, 3u, 5u})
        EXPECT_EQ(tree.count_within(q, r, stop), std::min<std::size_t>(stop, want.size()));
      EXPECT_EQ(tree.count_within(q, r, 0), 0u);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Clouds, KdTreeBrute, ::testing::Values(0, 1));

TEST(KdTree, RadiusIncludesExactBoundaryAndDuplicates) {
  const std::vector<Eigen::Vector3f> pts = {{0, 0, 0}, {2, 0, 0}, {0, 0, 0}, {0, 3, 0}};
  const KdTree tree(pts);
  std::vector<Neighbor> out;
  tree.radius({0, 0, 0}, 2.0f, out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].index, 0u);
  EXPECT_EQ(out[1].index, 2u);
  EXPECT_EQ(out[2].index, 1u);
  EXPECT_EQ(out[2].distance_sq, 4.0f);
  tree.knn({0, 0, 0}, 2, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].index, 0u);
  EXPECT_EQ(out[1].index, 2u);
}

TEST(KdTree, EmptyTreeIsSafe) {
  const std::vector<Eigen::Vector3f> none;
  const KdTree tree(none);
  EXPECT_EQ(tree.size(), 0u);
  std::vector<Neighbor> out{{1, 1.f}};
  tree.knn({0, 0, 0}, 5, out);
  EXPECT_TRUE(out.empty());
  tree.radius({0, 0, 0}, 10.f, out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(tree.count_within({0, 0, 0}, 10.f, 5), 0u);
  const Neighbor nn = tree.nearest({0, 0, 0});
  EXPECT_EQ(nn.index, std::numeric_limits<std::uint32_t>::max());
  EXPECT_TRUE(std::isinf(nn.distance_sq));
  EXPECT_TRUE(nearest_batch(tree, {{0, 0, 0}, {1, 1, 1}})[1].index == std::numeric_limits<std::uint32_t>::max());
}

TEST(KdTree, KLargerThanCloudAndBadArguments) {
  const std::vector<Eigen::Vector3f> pts = {{0, 0, 0}, {1, 0, 0}, {5, 0, 0}};
  const KdTree tree(pts);
  std::vector<Neighbor> out;
  tree.knn({4, 0, 0}, 10, out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].index, 2u);
  EXPECT_EQ(out[2].index, 0u);
  tree.knn({4, 0, 0}, 0, out);
  EXPECT_TRUE(out.empty());
  tree.knn({4, 0, 0}, -3, out);
  EXPECT_TRUE(out.empty());
  tree.radius({4, 0, 0}, -1.f, out);
  EXPECT_TRUE(out.empty());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  tree.knn({nan, 0, 0}, 2, out);
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(tree.count_within({0, nan, 0}, 100.f, 10), 0u);
}

TEST(KdTree, NonFinitePointsAreNeverReturned) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<Eigen::Vector3f> pts = random_cloud(5, 400);
  for (std::size_t i = 0; i < pts.size(); i += 7) pts[i] = {nan, nan, nan};
  pts[3] = {inf, 0, 0};
  const KdTree tree(pts);
  EXPECT_EQ(tree.size(), pts.size());
  std::vector<Neighbor> got;
  for (const auto& q : queries(9, 30, 55.f)) {
    const auto all = brute_sorted(pts, q);
    tree.knn(q, 12, got);
    expect_same(got, std::vector<Neighbor>(all.begin(), all.begin() + 12));
    tree.radius(q, 20.f, got);
    std::vector<Neighbor> want;
    for (const auto& nb : all)
      if (nb.distance_sq <= 400.f) want.push_back(nb);
    expect_same(got, want);
  }
}

TEST(KdTree, MoveKeepsTheIndex) {
  const auto pts = random_cloud(2, 500);
  KdTree a(pts);
  const Neighbor before = a.nearest({1, 2, 3});
  KdTree b(std::move(a));
  const Neighbor after = b.nearest({1, 2, 3});
  EXPECT_EQ(before.index, after.index);
  KdTree c(std::vector<Eigen::Vector3f>{});
  c = std::move(b);
  EXPECT_EQ(c.nearest({1, 2, 3}).index, before.index);
}

TEST(KdTree, BatchesMatchSingleQueriesForAnyThreadCount) {
  const auto pts = random_cloud(4, 20000);
  const KdTree tree(pts);
  const auto q = random_cloud(8, 30000);
  std::vector<Neighbor> one, two;
  std::vector<std::vector<Neighbor>> k1, k2;
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
    one = nearest_batch(tree, q);
    k1 = knn_batch(tree, q, 5);
  }
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
    two = nearest_batch(tree, q);
    k2 = knn_batch(tree, q, 5);
  }
  ASSERT_EQ(one.size(), q.size());
  std::vector<Neighbor> single;
  for (std::size_t i = 0; i < q.size(); ++i) {
    EXPECT_EQ(one[i].index, two[i].index);
    const Neighbor nn = tree.nearest(q[i]);
    EXPECT_EQ(one[i].index, nn.index);
    EXPECT_EQ(one[i].distance_sq, nn.distance_sq);
    ASSERT_EQ(k1[i].size(), 5u);
    for (int j = 0; j < 5; ++j) EXPECT_EQ(k1[i][j].index, k2[i][j].index);
    EXPECT_EQ(k1[i][0].index, nn.index);
  }
}

// sort_for_search: the same points and attributes, permuted together; a tree over the sorted cloud uses the
// points in place (identity spatial order) and answers as a tree over the original cloud, indices mapped.
class SortForSearch : public ::testing::TestWithParam<std::size_t> {};

// Both ways of permuting: a copy per attribute (the default up to 4 Mi points) and in place (copy_max_points 0).
INSTANTIATE_TEST_SUITE_P(CopyOrInPlace, SortForSearch, ::testing::Values(std::size_t(4) << 20, std::size_t(0)));

TEST_P(SortForSearch, PermutesEveryAttributeAndTheNextTreeUsesThePointsInPlace) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Cloud cloud;
  cloud.points = random_cloud(21, 5000);
  for (std::size_t i = 0; i < cloud.points.size(); i += 97) cloud.points[i] = {nan, nan, nan};
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    cloud.normals.emplace_back(float(i), 0.f, 1.f);
    cloud.colors.push_back({std::uint8_t(i % 251), std::uint8_t(i / 251 % 256), 7});
    cloud.intensities.push_back(float(i) * 0.5f);
  }
  cloud.scalars.push_back({"id", {}});
  for (std::size_t i = 0; i < cloud.points.size(); ++i) cloud.scalars[0].values.push_back(float(i));
  const Cloud original = cloud;
  const KdTree before(original.points);
  ASSERT_NE(before.spatial_order().ids, nullptr);  // random order: the tree copies

  const KdTree sorting = sort_for_search(cloud, GetParam());
  ASSERT_EQ(cloud.size(), original.size());
  std::vector<bool> seen(cloud.size(), false);
  std::size_t finite = 0;
  for (std::size_t j = 0; j < cloud.size(); ++j) {
    const auto i = static_cast<std::size_t>(cloud.scalars[0].values[j]);  // where slot j came from
    ASSERT_LT(i, cloud.size());
    EXPECT_FALSE(seen[i]);
    seen[i] = true;
    if (original.points[i].allFinite()) {
      EXPECT_EQ(j, finite++) << "finite points first";
      EXPECT_EQ(cloud.points[j], original.points[i]);
    } else {
      EXPECT_FALSE(cloud.points[j].allFinite());
    }
    EXPECT_EQ(cloud.normals[j], original.normals[i]);
    EXPECT_EQ(cloud.colors[j], original.colors[i]);
    EXPECT_EQ(cloud.intensities[j], original.intensities[i]);
  }

  const KdTree after(cloud.points);
  // no copy: the points are used where they are, by the tree the sort returned and by a tree built afterwards
  EXPECT_EQ(after.spatial_order().ids, nullptr);
  EXPECT_EQ(sorting.spatial_order().ids, nullptr);
  EXPECT_EQ(sorting.spatial_order().size(), finite);
  EXPECT_EQ(&sorting.points(), &cloud.points);
  std::vector<Neighbor> a, b, c;
  for (const auto& q : queries(5, 40, 55.f)) {
    before.knn(q, 9, a);
    after.knn(q, 9, b);
    sorting.knn(q, 9, c);
    ASSERT_EQ(a.size(), b.size());
    ASSERT_EQ(a.size(), c.size());
    for (std::size_t r = 0; r < a.size(); ++r) {
      EXPECT_EQ(a[r].distance_sq, b[r].distance_sq);
      EXPECT_EQ(original.points[a[r].index], cloud.points[b[r].index]);
      EXPECT_EQ(b[r].index, c[r].index);
      EXPECT_EQ(b[r].distance_sq, c[r].distance_sq);
    }
    EXPECT_EQ(before.count_within(q, 6.f, 1000), after.count_within(q, 6.f, 1000));
    EXPECT_EQ(after.count_within(q, 6.f, 1000), sorting.count_within(q, 6.f, 1000));
  }
  const Cloud sorted = cloud;
  (void)sort_for_search(cloud, GetParam());  // sorting again changes nothing
  EXPECT_EQ(cloud.scalars[0].values, sorted.scalars[0].values);
}

// MovingNearest gives what the tree gives, for points walking in small and large steps (most answers from the
// lists), within several distances, on the tie lattice (steps of whole units keep the walkers on it) and in a
// random cloud, with the whole target smaller than a list too.
TEST(MovingNearest, EveryAnswerIsTheTreesAnswer) {
  struct Case {
    std::vector<Eigen::Vector3f> pts;
    float step;
  };
  const std::vector<Case> cases = {{random_cloud(21, 4000), 0.05f}, {random_cloud(22, 4000), 1.5f},
                                   {tie_cloud(23, 1500), 0.5f}, {random_cloud(24, 5), 0.3f}};
  for (const Case& cs : cases) {
    const KdTree tree(cs.pts);
    const std::size_t walkers = 40;
    // Lists for the even walkers first, then for every third (the lists of both kept): the others from the tree.
    std::vector<std::uint32_t> even, thirds;
    for (std::uint32_t w = 0; w < walkers; ++w) {
      if (w % 2 == 0) even.push_back(w);
      if (w % 3 == 0) thirds.push_back(w);
    }
    MovingNearest moving(tree, even);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> start(-40.f, 40.f);
    std::uniform_int_distribution<int> dir(-1, 1);
    std::vector<Eigen::Vector3f> at(walkers);
    for (auto& p : at) p = {std::round(start(rng)), std::round(start(rng)), std::round(start(rng)) * 0.5f};
    std::vector<std::uint32_t> hint(walkers, std::numeric_limits<std::uint32_t>::max());
    for (int step = 0; step < 60; ++step) {
      if (step == 30) moving.serve(thirds);
      const float reach = step % 3 == 0 ? 1e4f : (step % 3 == 1 ? 3.0f : 0.6f);
      for (std::size_t w = 0; w < walkers; ++w) {
        at[w] += cs.step * Eigen::Vector3f(float(dir(rng)), float(dir(rng)), float(dir(rng)));
        const Neighbor want = tree.nearest(at[w], reach, std::numeric_limits<std::uint32_t>::max());
        const Neighbor got = moving.nearest(static_cast<std::uint32_t>(w), at[w], reach, hint[w]);
        ASSERT_EQ(got.index, want.index) << "step " << step << " walker " << w << " reach " << reach;
        if (want.index != std::numeric_limits<std::uint32_t>::max()) {
          EXPECT_EQ(got.distance_sq, want.distance_sq);
          hint[w] = got.index;
        }
      }
    }
  }
}
