// Mesh sampling against analytic truth: on-surface, counts, area weighting, determinism.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>

#include "ewis/core/error.hpp"
#include "ewis/sample/mesh_sampling.hpp"
#include "ewis/scene/primitives.hpp"

namespace {

using Eigen::Vector3d;

ewis::Scene sphere_scene(double r, int seg = 96, int rings = 48) {
  ewis::Scene s;
  const ewis::Mesh m = ewis::make_sphere(Vector3d(10, 20, 30), r, seg, rings);
  ewis::add_element(s, "sphere", m.vertices, m.triangles);
  return s;
}

TEST(MeshSampling, SphereSamplesLieOnTheSurfaceWithOutwardNormals) {
  const double r = 50, spacing = 2;
  const ewis::Scene s = sphere_scene(r);
  ewis::MeshSamplingParams p;
  p.spacing_mm = spacing;
  const ewis::MeshSamples out = ewis::sample_mesh(s, p);
  const double area = s.elements[0].area_mm2;
  EXPECT_NEAR(double(out.cloud.size()), area / (spacing * spacing), 1.0);
  ASSERT_EQ(out.cloud.normals.size(), out.cloud.size());
  ASSERT_EQ(out.element.size(), out.cloud.size());
  // Chord error of a 96 x 48 UV sphere: r (1 - cos(pi/48)) ~ 0.11 mm for r = 50.
  const double sagitta = r * (1 - std::cos(M_PI / 48));
  for (std::size_t i = 0; i < out.cloud.size(); ++i) {
    const Vector3d q = out.cloud.points[i].cast<double>() - Vector3d(10, 20, 30);
    ASSERT_LE(q.norm(), r + 1e-3);
    ASSERT_GE(q.norm(), r - sagitta - 1e-3);
    ASSERT_GT(out.cloud.normals[i].cast<double>().dot(q.normalized()), 0.99);
    ASSERT_NEAR(out.cloud.normals[i].norm(), 1.0, 1e-5);
    ASSERT_EQ(out.element[i], 0u);
    ASSERT_LT(out.triangle[i], s.triangle_count());
  }
  // The samples are spread over the whole sphere: centroid near the centre.
  Vector3d mean = Vector3d::Zero();
  for (const auto& q : out.cloud.points) mean += q.cast<double>();
  mean /= double(out.cloud.size());
  EXPECT_LT((mean - Vector3d(10, 20, 30)).norm(), 1.5);
}

TEST(MeshSampling, SamplesFollowTriangleArea) {
  // Two triangles in one element, areas 1 : 3.
  ewis::Scene s;
  ewis::add_element(s, "pair",
                    {Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(1, 0, 0), Eigen::Vector3f(0, 2, 0),
                     Eigen::Vector3f(5, 0, 0), Eigen::Vector3f(8, 0, 0), Eigen::Vector3f(5, 2, 0)},
                    {Eigen::Vector3i(0, 1, 2), Eigen::Vector3i(3, 4, 5)});
  ewis::MeshSamplingParams p;
  p.spacing_mm = 0.02;  // 4 / 0.0004 = 10000 samples
  const ewis::MeshSamples out = ewis::sample_mesh(s, p);
  ASSERT_EQ(out.cloud.size(), 10000u);
  std::size_t small = 0;
  for (std::size_t i = 0; i < out.cloud.size(); ++i) {
    small += out.triangle[i] == 0;
    // Inside its triangle.
    const Eigen::Vector3f q = out.cloud.points[i];
    if (out.triangle[i] == 0) {
      EXPECT_GE(q.x(), -1e-6f);
      EXPECT_GE(q.y(), -1e-6f);
      EXPECT_LE(q.x() + q.y() / 2, 1 + 1e-5f);
    } else {
      EXPECT_GE(q.x(), 5 - 1e-5f);
      EXPECT_LE((q.x() - 5) / 3 + q.y() / 2, 1 + 1e-5f);
    }
  }
  // Binomial: mean 2500, sd ~43; 5 sd.
  EXPECT_NEAR(double(small), 2500.0, 220.0);
  // Uniform inside a triangle: the mean is the centroid.
  Vector3d mean = Vector3d::Zero();
  for (std::size_t i = 0; i < out.cloud.size(); ++i)
    if (out.triangle[i] == 1) mean += out.cloud.points[i].cast<double>();
  mean /= double(out.cloud.size() - small);
  EXPECT_NEAR(mean.x(), 6.0, 0.05);
  EXPECT_NEAR(mean.y(), 2.0 / 3.0, 0.05);
}

ewis::Scene several() {
  ewis::Scene s;
  const ewis::Mesh box = ewis::make_box(Vector3d(0, 0, 0), Vector3d(100, 50, 20));
  const ewis::Mesh tube = ewis::make_tube({Vector3d(0, 0, 30), Vector3d(50, 0, 40), Vector3d(100, 20, 40)}, 5, 24);
  const ewis::Mesh sph = ewis::make_sphere(Vector3d(0, 100, 0), 15);
  ewis::add_element(s, "box", box.vertices, box.triangles);
  ewis::add_element(s, "tube", tube.vertices, tube.triangles);
  ewis::add_element(s, "sphere", sph.vertices, sph.triangles);
  return s;
}

TEST(MeshSampling, DeterministicAndThreadCountIndependent) {
  const ewis::Scene s = several();
  ewis::MeshSamplingParams p;
  p.spacing_mm = 0.45;  // > 4096 samples per element: several RNG blocks
  p.seed = 42;
  const ewis::MeshSamples a = ewis::sample_mesh(s, p);
  ewis::MeshSamples b;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    b = ewis::sample_mesh(s, p);
  }
  ASSERT_EQ(a.cloud.size(), b.cloud.size());
  EXPECT_GT(a.cloud.size(), 2u * 4096u);
  for (std::size_t i = 0; i < a.cloud.size(); ++i) {
    ASSERT_EQ(a.cloud.points[i], b.cloud.points[i]);
    ASSERT_EQ(a.triangle[i], b.triangle[i]);
  }
  p.seed = 43;
  const ewis::MeshSamples c = ewis::sample_mesh(s, p);
  ASSERT_EQ(c.cloud.size(), a.cloud.size());
  EXPECT_NE(c.cloud.points[0], a.cloud.points[0]);
}

TEST(MeshSampling, PerElementCountsSelectionAndCap) {
  const ewis::Scene s = several();
  ewis::MeshSamplingParams p;
  p.spacing_mm = 1.5;
  const ewis::MeshSamples all = ewis::sample_mesh(s, p);
  std::vector<std::size_t> per(3, 0);
  for (std::uint32_t e : all.element) per[e]++;
  for (int e = 0; e < 3; ++e) EXPECT_NEAR(double(per[e]), s.elements[e].area_mm2 / 2.25, 0.5);

  p.elements = {2, 0};
  const ewis::MeshSamples two = ewis::sample_mesh(s, p);
  EXPECT_EQ(two.cloud.size(), per[2] + per[0]);
  EXPECT_EQ(two.element.front(), 2u);
  EXPECT_EQ(two.element.back(), 0u);

  p.elements.clear();
  p.max_points = 1000;
  const ewis::MeshSamples capped = ewis::sample_mesh(s, p);
  EXPECT_LE(capped.cloud.size(), 1000u);
  EXPECT_GT(capped.cloud.size(), 900u);
  std::vector<std::size_t> per_capped(3, 0);
  for (std::uint32_t e : capped.element) per_capped[e]++;
  for (int e = 0; e < 3; ++e) EXPECT_GT(per_capped[e], 0u);

  // A tiny element still gets one point.
  ewis::Scene t = s;
  ewis::add_element(t, "speck", {Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(0.01f, 0, 0), Eigen::Vector3f(0, 0.01f, 0)},
                    {Eigen::Vector3i(0, 1, 2)});
  p.max_points = 0;
  p.elements = {3};
  EXPECT_EQ(ewis::sample_mesh(t, p).cloud.size(), 1u);
}

TEST(MeshSampling, BadParametersThrow) {
  const ewis::Scene s = several();
  ewis::MeshSamplingParams p;
  p.spacing_mm = 0;
  EXPECT_THROW(ewis::sample_mesh(s, p), ewis::InputError);
  p.spacing_mm = 1;
  p.elements = {5};
  EXPECT_THROW(ewis::sample_mesh(s, p), ewis::InputError);
  EXPECT_TRUE(ewis::sample_mesh(ewis::Scene{}, ewis::MeshSamplingParams{}).cloud.empty());
}

}  // namespace

// `keep` returns exactly the full result's accepted samples, in order (a CAD view without the whole CAD's
// samples in memory).
TEST(MeshSampling, KeepGivesTheFilteredFullResultInOrder) {
  const ewis::Scene s = several();
  ewis::MeshSamplingParams p;
  p.spacing_mm = 0.7;
  p.seed = 5;
  const ewis::MeshSamples all = ewis::sample_mesh(s, p);
  auto in_view = [](const Eigen::Vector3f& q, const Eigen::Vector3f& n) {
    return q.x() > 20.f && q.x() < 70.f && n.z() > -0.2f;  // a box and a facing test, as a registration view
  };
  p.keep = in_view;
  const ewis::MeshSamples view = ewis::sample_mesh(s, p);
  std::size_t j = 0;
  for (std::size_t i = 0; i < all.cloud.size(); ++i) {
    if (!in_view(all.cloud.points[i], all.cloud.normals[i])) continue;
    ASSERT_LT(j, view.cloud.size());
    EXPECT_EQ(view.cloud.points[j], all.cloud.points[i]);
    EXPECT_EQ(view.cloud.normals[j], all.cloud.normals[i]);
    EXPECT_EQ(view.element[j], all.element[i]);
    EXPECT_EQ(view.triangle[j], all.triangle[i]);
    ++j;
  }
  EXPECT_EQ(j, view.cloud.size());
  EXPECT_GT(j, all.cloud.size() / 5);
  EXPECT_LT(j, all.cloud.size() * 4 / 5);
}
