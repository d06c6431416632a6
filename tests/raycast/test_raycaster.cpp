// Raycaster against analytic geometry: exact distances, elements, normals, occlusion, masks, batches.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ewis/raycast/raycaster.hpp"
#include "ewis/scene/primitives.hpp"

namespace {

using Eigen::Vector3d;
using Eigen::Vector3f;

ewis::Scene box_and_sphere() {
  ewis::Scene s;
  const ewis::Mesh box = ewis::make_box(Vector3d(-10, -10, 90), Vector3d(10, 10, 110));
  const ewis::Mesh sphere = ewis::make_sphere(Vector3d(0, 0, 200), 30, 64, 32);
  ewis::add_element(s, "box", box.vertices, box.triangles);
  ewis::add_element(s, "sphere", sphere.vertices, sphere.triangles);
  return s;
}

TEST(Raycaster, HitsBoxFaceAtExactDistanceWithNormal) {
  const ewis::Scene s = box_and_sphere();
  const ewis::Raycaster rc(s);
  // Non-unit direction: the distance is still along the unit direction.
  const ewis::Hit h = rc.cast({Vector3f(1, 2, 0), Vector3f(0, 0, 5)});
  ASSERT_TRUE(h.hit());
  EXPECT_FLOAT_EQ(h.distance_mm, 90.f);
  EXPECT_EQ(h.element, 0u);
  EXPECT_LT(h.triangle, 12u);
  EXPECT_NEAR((h.normal - Vector3f(0, 0, -1)).norm(), 0, 1e-6);
  // Oblique ray at the +x face from outside: distance = 25 / cos(angle).
  const Vector3f dir = Vector3f(-1, 0.2f, 0.1f).normalized();
  const ewis::Hit g = rc.cast({Vector3f(35, 0, 100), dir});
  ASSERT_TRUE(g.hit());
  EXPECT_NEAR(g.distance_mm, 25.0 / std::abs(dir.x()), 1e-4);
  EXPECT_NEAR((g.normal - Vector3f(1, 0, 0)).norm(), 0, 1e-6);
  // From inside the box the normal faces the ray too.
  const ewis::Hit in = rc.cast({Vector3f(0, 0, 100), Vector3f(1, 0, 0)});
  ASSERT_TRUE(in.hit());
  EXPECT_FLOAT_EQ(in.distance_mm, 10.f);
  EXPECT_NEAR((in.normal - Vector3f(-1, 0, 0)).norm(), 0, 1e-6);
}

TEST(Raycaster, MissesTmaxAndBadRays) {
  const ewis::Scene s = box_and_sphere();
  const ewis::Raycaster rc(s);
  EXPECT_FALSE(rc.cast({Vector3f(0, 0, 0), Vector3f(0, 0, -1)}).hit());
  EXPECT_FALSE(rc.cast({Vector3f(0, 0, 0), Vector3f(0, 0, 1), 89.f}).hit());
  EXPECT_FALSE(rc.cast({Vector3f(0, 0, 0), Vector3f(0, 0, 0)}).hit());
  EXPECT_FALSE(rc.cast({Vector3f(0, 0, 0), Vector3f(NAN, 0, 1)}).hit());
  EXPECT_FALSE(rc.occluded({Vector3f(0, 0, 0), Vector3f(0, 0, 1), 89.f}));
  EXPECT_TRUE(rc.occluded({Vector3f(0, 0, 0), Vector3f(0, 0, 1), 91.f}));
}

TEST(Raycaster, BoxInFrontOccludesSphere) {
  const ewis::Scene s = box_and_sphere();
  const ewis::Raycaster rc(s);
  const ewis::Hit h = rc.cast({Vector3f(0, 0, 0), Vector3f(0, 0, 1)});
  EXPECT_EQ(h.element, 0u);
  // Beside the box the sphere is seen at distance 200 - sqrt(30^2 - 15^2) along z.
  const ewis::Hit side = rc.cast({Vector3f(15, 0, 0), Vector3f(0, 0, 1)});
  ASSERT_EQ(side.element, 1u);
  EXPECT_NEAR(side.distance_mm, 200 - std::sqrt(900.0 - 225.0), 0.5);  // chord error of the UV sphere
  const Vector3f to_centre = (Vector3f(0, 0, 200) - Vector3f(15, 0, 174)).normalized();
  EXPECT_GT(side.normal.dot(-to_centre), 0.99f);
}

TEST(Raycaster, IncludeMaskRemovesElements) {
  const ewis::Scene s = box_and_sphere();
  const ewis::Raycaster only_sphere(s, {false, true});
  const ewis::Hit h = only_sphere.cast({Vector3f(0, 0, 0), Vector3f(0, 0, 1)});
  ASSERT_EQ(h.element, 1u);
  EXPECT_NEAR(h.distance_mm, 170, 1e-3);  // the pole vertex
  EXPECT_GE(h.triangle, s.elements[1].first_triangle);
  EXPECT_FALSE(only_sphere.included(0));
  const ewis::Raycaster none(s, {false, false});
  EXPECT_FALSE(none.cast({Vector3f(0, 0, 0), Vector3f(0, 0, 1)}).hit());
  EXPECT_FALSE(none.occluded({Vector3f(0, 0, 0), Vector3f(0, 0, 1)}));
}

TEST(Raycaster, BatchMatchesSingleRaysForEveryPacketWidth) {
  const ewis::Scene s = box_and_sphere();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<ewis::Ray> rays(5000);
  for (auto& r : rays) {
    r.origin = Vector3f(u(rng) * 50, u(rng) * 50, u(rng) * 20);
    r.direction = Vector3f(u(rng) * 0.4f, u(rng) * 0.4f, 1.f) * (1.f + u(rng) * 0.5f);
  }
  rays[17].direction.setZero();
  const ewis::Raycaster single(s, {}, 1);
  std::vector<ewis::Hit> ref;
  single.cast(rays, ref);
  ASSERT_EQ(ref.size(), rays.size());
  std::size_t hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const ewis::Hit h = single.cast(rays[i]);
    EXPECT_EQ(h.element, ref[i].element);
    EXPECT_EQ(h.distance_mm, ref[i].distance_mm);
    hits += h.hit();
  }
  EXPECT_GT(hits, 500u);
  for (int width : {4, 8, 16, 0}) {
    const ewis::Raycaster rc(s, {}, width);
    std::vector<ewis::Hit> out;
    rc.cast(rays, out);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      if (out[i].element != ref[i].element || out[i].triangle != ref[i].triangle) ++differ;
      if (out[i].hit() && ref[i].hit()) {
        EXPECT_NEAR(out[i].distance_mm, ref[i].distance_mm, 1e-3);
      }
    }
    EXPECT_EQ(differ, 0u) << "packet width " << width;
  }
}

TEST(Raycaster, MovedRaycasterStillWorks) {
  const ewis::Scene s = box_and_sphere();
  ewis::Raycaster a(s);
  ewis::Raycaster b = std::move(a);
  EXPECT_TRUE(b.cast({Vector3f(0, 0, 0), Vector3f(0, 0, 1)}).hit());
  EXPECT_EQ(&b.scene(), &s);
}

}  // namespace
