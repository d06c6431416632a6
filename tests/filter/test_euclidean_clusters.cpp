#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <limits>
#include <random>

#include "ewis/filter/euclidean_clusters.hpp"

using namespace ewis;

namespace {

// Blobs: points on a 0.5 mm lattice inside balls of given radii, far apart (>= 20 mm), appended in a
// shuffled order so that cluster membership is not contiguous in the index space.
struct Blobs {
  std::vector<Eigen::Vector3f> points;
  std::vector<std::vector<std::uint32_t>> truth;  // per blob, sorted indices
};

Blobs make_blobs(const std::vector<float>& radii, std::size_t isolated) {
  std::vector<std::pair<int, Eigen::Vector3f>> tagged;
  for (std::size_t b = 0; b < radii.size(); ++b) {
    const Eigen::Vector3f c(30.f * b, 0, 0);
    const int m = int(radii[b] / 0.5f);
    for (int x = -m; x <= m; ++x)
      for (int y = -m; y <= m; ++y)
        for (int z = -m; z <= m; ++z)
          if ((x * x + y * y + z * z) * 0.25f <= radii[b] * radii[b])
            tagged.push_back({int(b), c + 0.5f * Eigen::Vector3f(float(x), float(y), float(z))});
  }
  for (std::size_t i = 0; i < isolated; ++i)
    tagged.push_back({-1, Eigen::Vector3f(15.f + 30.f * i, 12.f, 0)});  // between the blobs, alone
  std::mt19937 rng(3);
  std::shuffle(tagged.begin(), tagged.end(), rng);
  Blobs out;
  out.truth.resize(radii.size());
  for (std::size_t i = 0; i < tagged.size(); ++i) {
    out.points.push_back(tagged[i].second);
    if (tagged[i].first >= 0) out.truth[tagged[i].first].push_back(static_cast<std::uint32_t>(i));
  }
  return out;
}

}  // namespace

TEST(EuclideanClusters, SeparatedBlobsFoundExactly) {
  const Blobs b = make_blobs({3.f, 5.f, 2.f, 4.f}, 6);
  const KdTree tree(b.points);
  const ClusterResult r = euclidean_clusters(tree, {}, 0.6, 1);
  ASSERT_EQ(r.clusters.size(), 4u + 6u);
  // largest first: radii 5, 4, 3, 2
  EXPECT_EQ(r.clusters[0], b.truth[1]);
  EXPECT_EQ(r.clusters[1], b.truth[3]);
  EXPECT_EQ(r.clusters[2], b.truth[0]);
  EXPECT_EQ(r.clusters[3], b.truth[2]);
  for (std::size_t i = 5; i < r.clusters.size(); ++i) EXPECT_LT(r.clusters[i - 1][0], r.clusters[i][0]);
  EXPECT_EQ(r.rejected_clusters, 0u);

  // size limits drop the single points and the largest blob
  const ClusterResult lim = euclidean_clusters(tree, {}, 0.6, 2, b.truth[3].size());
  ASSERT_EQ(lim.clusters.size(), 3u);
  EXPECT_EQ(lim.clusters[0], b.truth[3]);
  EXPECT_EQ(lim.rejected_clusters, 7u);
  EXPECT_EQ(lim.rejected_points, 6u + b.truth[1].size());
}

TEST(EuclideanClusters, ToleranceIsInclusiveAndChainsConnect) {
  std::vector<Eigen::Vector3f> line;
  for (int i = 0; i < 50; ++i) line.emplace_back(i * 1.0f, 0, 0);  // a chain 1 mm apart
  for (int i = 0; i < 50; ++i) line.emplace_back(i * 1.5f, 10.f, 0);  // 1.5 mm apart
  const KdTree tree(line);
  const ClusterResult a = euclidean_clusters(tree, {}, 1.0, 1);
  ASSERT_EQ(a.clusters.size(), 51u);
  EXPECT_EQ(a.clusters[0].size(), 50u);
  EXPECT_EQ(a.clusters[0].front(), 0u);
  const ClusterResult b = euclidean_clusters(tree, {}, 1.5, 1);
  ASSERT_EQ(b.clusters.size(), 2u);
  EXPECT_EQ(b.clusters[1].front(), 50u);  // equal sizes: smallest index first
}

TEST(EuclideanClusters, SubsetRestrictsPointsAndLinks) {
  std::vector<Eigen::Vector3f> line;
  for (int i = 0; i < 10; ++i) line.emplace_back(i * 1.0f, 0, 0);
  const KdTree tree(line);
  // without point 5 the chain breaks in two; repeats and out-of-range indices are ignored
  const ClusterResult r = euclidean_clusters(tree, {9, 0, 1, 2, 3, 4, 6, 7, 8, 8, 1000}, 1.0, 1);
  ASSERT_EQ(r.clusters.size(), 2u);
  EXPECT_EQ(r.clusters[0], std::vector<std::uint32_t>({0, 1, 2, 3, 4}));
  EXPECT_EQ(r.clusters[1], std::vector<std::uint32_t>({6, 7, 8, 9}));
}

TEST(EuclideanClusters, EmptyDuplicatesAndNaNs) {
  EXPECT_TRUE(euclidean_clusters(KdTree(std::vector<Eigen::Vector3f>{}), {}, 1.0, 1).clusters.empty());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<Eigen::Vector3f> dup = {{0, 0, 0}, {5, 0, 0}, {nan, 0, 0}, {0, 0, 0}};
  const ClusterResult r = euclidean_clusters(KdTree(dup), {}, 0.0, 1);
  ASSERT_EQ(r.clusters.size(), 2u);  // the NaN point is in no cluster
  EXPECT_EQ(r.clusters[0], std::vector<std::uint32_t>({0, 3}));
  EXPECT_EQ(r.clusters[1], std::vector<std::uint32_t>({1}));
}

TEST(EuclideanClusters, SameForOneAndTwoThreads) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> u(0.f, 60.f);
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < 60000; ++i) pts.emplace_back(u(rng), u(rng), u(rng));  // percolation-like tangle
  const KdTree tree(pts);
  ClusterResult a, b;
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 1);
    a = euclidean_clusters(tree, {}, 1.0, 1);
  }
  {
    tbb::global_control gc(tbb::global_control::max_allowed_parallelism, 2);
    b = euclidean_clusters(tree, {}, 1.0, 1);
  }
  EXPECT_EQ(a.clusters, b.clusters);
  EXPECT_GT(a.clusters.size(), 10u);
}
