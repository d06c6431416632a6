#include <gtest/gtest.h>

#include <cmath>

#include "ewis/sim/route.hpp"
#include "ewis/sim/shapes.hpp"

using namespace ewis;
using namespace ewis::sim;
using V3 = Eigen::Vector3d;

TEST(Route, FilletRouteHasAnalyticLengthAndRadius) {
  const auto r = fillet_route({V3(0, 0, 0), V3(100, 0, 0), V3(100, 100, 0)}, {0, 30, 0});
  ASSERT_TRUE(r);
  EXPECT_NEAR(r->length_mm(), 70 + 70 + M_PI / 2 * 30, 1e-9);
  EXPECT_DOUBLE_EQ(r->min_curvature_radius_mm(), 30.0);
  EXPECT_NEAR((r->end() - V3(100, 100, 0)).norm(), 0.0, 1e-9);
  const auto pts = sample_route(*r, 0.5);
  EXPECT_NEAR(polyline_length(pts), r->length_mm(), 1e-3);
  EXPECT_NEAR(polyline_min_curvature_radius(pts, 5.0), 30.0, 0.05);
  // Tangent continuity at the arc's ends.
  EXPECT_NEAR((r->tangent(69.999) - r->tangent(70.001)).norm(), 0.0, 1e-3);
}

TEST(Route, NonPlanarCornersAndStraightRoutes) {
  const auto r = fillet_route({V3(0, 0, 0), V3(100, 0, 0), V3(150, 80, 40), V3(260, 60, 40)}, {0, 40, 25, 0});
  ASSERT_TRUE(r);
  const auto pts = sample_route(*r, 0.25);
  for (std::size_t i = 1; i < pts.size(); ++i) ASSERT_LE((pts[i] - pts[i - 1]).norm(), 0.25 + 1e-9);
  EXPECT_NEAR(polyline_length(pts), r->length_mm(), 2e-3);
  EXPECT_NEAR(polyline_min_curvature_radius(pts, 4.0), 25.0, 0.05);
  const auto s = fillet_route({V3(0, 0, 0), V3(50, 0, 0), V3(100, 0, 0)}, {0, 10, 0});
  ASSERT_TRUE(s);
  EXPECT_TRUE(std::isinf(s->min_curvature_radius_mm()));
  EXPECT_TRUE(std::isinf(polyline_min_curvature_radius(sample_route(*s, 1.0), 5.0)));
}

TEST(Route, FilletThatDoesNotFitIsRejected) {
  EXPECT_FALSE(fillet_route({V3(0, 0, 0), V3(20, 0, 0), V3(20, 20, 0)}, {0, 50, 0}));
  EXPECT_FALSE(fillet_route({V3(0, 0, 0), V3(0, 0, 0), V3(20, 20, 0)}, {0, 5, 0}));
}

TEST(Route, HelixCurvatureRadiusIsAnalytic) {
  auto r = fillet_route({V3(0, 0, 0), V3(50, 0, 0)}, {0, 0});
  ASSERT_TRUE(r);
  const double a = 20, b = 5;
  ASSERT_TRUE(append_helix(*r, V3(0, 1, 0), a, b, 1.5 * M_PI));
  append_straight(*r, 10);
  EXPECT_NEAR(r->min_curvature_radius_mm(), (a * a + b * b) / a, 1e-12);
  EXPECT_NEAR(r->length_mm(), 50 + 1.5 * M_PI * std::sqrt(a * a + b * b) + 10, 1e-9);
  // Tangent continuity into and out of the helix, and the rise of 2*pi*b per turn.
  EXPECT_NEAR((r->tangent(49.999) - r->tangent(50.001)).norm(), 0.0, 1e-3);
  const double lh = 1.5 * M_PI * std::sqrt(a * a + b * b);
  EXPECT_NEAR((r->tangent(50 + lh - 1e-3) - r->tangent(50 + lh + 1e-3)).norm(), 0.0, 1e-3);
  // The rise along the helix axis is b per radian (the axis leans: the helix leaves the run tangentially).
  const auto& h = r->pieces[1];
  EXPECT_NEAR((r->at(50 + lh) - r->at(50)).dot(h.w), 1.5 * M_PI * b, 1e-9);
  const auto pts = sample_route(*r, 0.25);
  EXPECT_NEAR(polyline_length(pts), r->length_mm(), 1e-3);
  EXPECT_NEAR(polyline_min_curvature_radius(pts, 3.0), 21.25, 0.03);
}

TEST(Shapes, DistancesAreExact) {
  const Shape box = make_aabb_shape(V3(0, 0, 0), V3(10, 20, 30));
  EXPECT_NEAR(distance_to_shape(box, V3(13, 10, 15)), 3.0, 1e-12);
  EXPECT_NEAR(distance_to_shape(box, V3(13, 24, 15)), 5.0, 1e-12);
  EXPECT_EQ(distance_to_shape(box, V3(5, 5, 5)), 0.0);
  const Shape sph = make_sphere_shape(V3(1, 2, 3), 4);
  EXPECT_NEAR(distance_to_shape(sph, V3(1, 2, 10)), 3.0, 1e-12);
  const Shape cyl = make_cylinder_shape(V3(0, 0, 0), V3(0, 0, 100), 5);
  EXPECT_NEAR(distance_to_shape(cyl, V3(8, 0, 50)), 3.0, 1e-12);
  EXPECT_NEAR(distance_to_shape(cyl, V3(8, 0, 104)), 5.0, 1e-12);
  const Shape tor = make_torus_shape(V3(0, 0, 0), V3(1, 0, 0), 20, 3);
  EXPECT_NEAR(distance_to_shape(tor, V3(0, 0, 30)), 7.0, 1e-12);
}

TEST(Shapes, TubeGapsAreSurfaceToSurface) {
  const auto a = fillet_route({V3(-100, 0, 20), V3(100, 0, 20)}, {0, 0});
  const auto b = fillet_route({V3(3, -100, 50), V3(3, 100, 50)}, {0, 0});
  ASSERT_TRUE(a && b);
  const Tube ta{&*a, 5.0}, tb{&*b, 6.0};
  EXPECT_NEAR(tube_tube_gap(ta, tb).gap_mm, 30 - 11, 1e-6);
  Solid s;
  s.shapes.push_back(make_sphere_shape(V3(50.3, 0, 0), 3));
  const GapResult g = tube_solid_gap(ta, s);
  EXPECT_NEAR(g.gap_mm, 20 - 5 - 3, 1e-6);
  EXPECT_NEAR(g.on_cable.x(), 50.3, 1e-3);
  // An arc around a sphere: the gap is the arc radius minus radii.
  const auto arc = fillet_route({V3(-100, 0, 0), V3(0, 0, 0), V3(0, 100, 0)}, {0, 40, 0});
  Solid c;
  const V3 center(-40, 40, 0);
  c.shapes.push_back(make_sphere_shape(center, 10));
  EXPECT_NEAR(tube_solid_gap({&*arc, 4.0}, c).gap_mm, 40 - 10 - 4, 1e-6);
}
