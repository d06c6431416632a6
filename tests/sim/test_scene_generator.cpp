#include <gtest/gtest.h>

#include <cmath>

#include "ewis/sim/campaign.hpp"
#include "ewis/sim/scene_generator.hpp"

using namespace ewis;
using namespace ewis::sim;
using V3 = Eigen::Vector3d;

namespace {

double point_segment(const V3& p, const V3& a, const V3& b) {
  const V3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / std::max(1e-300, ab.squaredNorm()), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

const SimCable& cable(const SimScene& s, const std::string& name) {
  for (const auto& c : s.cables)
    if (c.name == name) return c;
  throw std::runtime_error("no cable " + name);
}

// Gap recomputed independently: the as-built TUBE MESH's vertices against the other solid (within the
// tessellation's sag), or centreline samples against the other centreline polyline.
double recomputed_gap(const SimScene& s, const Scene& built, const SimGap& g) {
  const SimCable& c = cable(s, g.cable);
  for (const auto& o : s.cables)
    if (o.name == g.with) {
      const auto pa = sample_route(c.as_built, 0.5), pb = sample_route(o.as_built, 0.5);
      double best = 1e300;
      for (const auto& p : pa)
        for (std::size_t j = 1; j < pb.size(); ++j)
          if ((p - pb[j]).squaredNorm() < (best + 2) * (best + 2)) best = std::min(best, point_segment(p, pb[j - 1], pb[j]));
      return best - 0.5 * (c.diameter_mm + o.diameter_mm);
    }
  const Solid* solid = nullptr;
  for (const auto& r : s.rigids)
    if (r.name == g.with) solid = &r.solid;
  const Element& e = built.elements[built.find(c.name)];
  double best = 1e300;
  for (std::uint32_t t = e.first_triangle; t < e.first_triangle + e.triangle_count; ++t)
    for (int k = 0; k < 3; ++k) best = std::min(best, solid->distance(built.vertices[built.triangles[t][k]].cast<double>()));
  return best;
}

void check_truth(const SimScene& s) {
  ASSERT_GE(s.cables.size(), 1u);
  for (const auto& c : s.cables) {
    const auto pts = sample_route(c.as_built, 0.5);
    EXPECT_NEAR(polyline_length(pts), c.as_built.length_mm(), 1e-3 * c.as_built.length_mm()) << c.name;
    const double r = c.as_built.min_curvature_radius_mm();
    double shortest_arc = 1e300;
    for (const auto& piece : c.as_built.pieces)
      if (piece.kind == RoutePiece::Kind::Helix) shortest_arc = std::min(shortest_arc, piece.length_mm());
    const double rn = polyline_min_curvature_radius(pts, std::min({4.0, 0.3 * r, 0.25 * shortest_arc}));
    if (std::isfinite(r))
      EXPECT_NEAR(rn, r, 0.005 * r) << c.name;
    else
      EXPECT_TRUE(std::isinf(rn));
    EXPECT_GE(c.diameter_mm, 3.0);
    EXPECT_LE(c.diameter_mm, 30.0);
    // Nominal (CAD) and as-built differ, but by millimetres, not centimetres.
    double dev = 0;
    for (const auto& p : sample_route(c.as_built, 5.0)) {
      double best = 1e300;
      const auto nom = sample_route(c.nominal, 1.0);
      for (const auto& q : nom) best = std::min(best, (p - q).norm());
      dev = std::max(dev, best);
    }
    EXPECT_GT(dev, 0.5) << c.name;
    EXPECT_LT(dev, 25.0) << c.name;
  }
  const Scene built = as_built_scene(s);
  for (const auto& g : s.gaps) {
    if (g.gap_mm > 60) continue;  // far neighbours: only the near ones matter to the rules
    EXPECT_NEAR(recomputed_gap(s, built, g), g.gap_mm, 0.12) << g.cable << " vs " << g.with;
  }
}

}  // namespace

TEST(SceneGenerator, CleanScenesKeepEveryRuleWithMargin) {
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    SceneParams p;
    p.seed = seed;
    const SimScene s = generate_scene(p);
    EXPECT_TRUE(s.defects.empty()) << seed;
    for (const auto& c : s.cables) {
      const double r = c.as_built.min_curvature_radius_mm();
      if (std::isfinite(r)) {
        EXPECT_GE(r, 1.2 * c.allowed_bend_radius_mm) << seed << " " << c.name;
      }
      EXPECT_GE(r / c.diameter_mm, 2.9);
    }
    for (const auto& g : s.gaps) {
      const SimCable* c = nullptr;
      for (const auto& cc : s.cables)
        if (cc.name == g.cable) c = &cc;
      EXPECT_GE(g.gap_mm, c->clearance_mm + 2.0) << seed << " " << g.cable << " " << g.with;
    }
  }
}

TEST(SceneGenerator, TruthIsSelfConsistent) {
  const DefectKind kinds[] = {DefectKind::None, DefectKind::Bend, DefectKind::Clearance, DefectKind::ForeignObject};
  std::uint64_t seed = 100;
  for (DefectKind k : kinds) {
    SceneParams p;
    p.seed = ++seed;
    p.defect = k;
    p.cables = 3;
    const SimScene s = generate_scene(p);
    check_truth(s);
  }
}

TEST(SceneGenerator, RequestedDefectsArePresentAndClear) {
  struct Case {
    DefectKind kind;
    std::string with;
  };
  const Case cases[] = {{DefectKind::Bend, ""},
                        {DefectKind::Clearance, "pipe"},
                        {DefectKind::Clearance, "bracket"},
                        {DefectKind::Clearance, "cable"},
                        {DefectKind::ForeignObject, ""}};
  std::uint64_t seed = 7;
  for (const auto& cs : cases) {
    SceneParams p;
    p.seed = ++seed;
    p.defect = cs.kind;
    p.clearance_with = cs.with;
    const SimScene s = generate_scene(p);
    ASSERT_FALSE(s.defects.empty()) << defect_kind_name(cs.kind) << " " << cs.with;
    for (const auto& d : s.defects) {
      EXPECT_EQ(d.kind, defect_kind_name(cs.kind));
      const SimCable& c = cable(s, d.element);
      if (d.kind == "bend") {
        EXPECT_LE(d.radius_mm, 0.85 * c.allowed_bend_radius_mm);
        EXPECT_NEAR(d.radius_mm, c.as_built.min_curvature_radius_mm(), 1e-9);
        // The CAD's bend was fine: only the build is wrong.
        EXPECT_GE(c.nominal.min_curvature_radius_mm(), 1.2 * c.allowed_bend_radius_mm);
      } else {
        EXPECT_LE(d.gap_mm, c.clearance_mm - 1.0);
        EXPECT_GE(d.gap_mm, -1e-3);
        if (d.kind == "clearance") {
          if (cs.with == "cable") EXPECT_EQ(d.with.rfind("cable_", 0), 0u);
          else EXPECT_EQ(d.with.rfind(cs.with + "_", 0), 0u) << d.with;
        } else {
          EXPECT_TRUE(d.with.empty());
        }
      }
    }
    check_truth(s);
  }
}

TEST(SceneGenerator, SameSeedSameScene) {
  SceneParams p;
  p.seed = 42;
  p.defect = DefectKind::Random;
  const SimScene a = generate_scene(p), b = generate_scene(p);
  EXPECT_EQ(truth_to_json(a, a.camera_to_cad, nullptr), truth_to_json(b, b.camera_to_cad, nullptr));
  p.seed = 43;
  const SimScene c = generate_scene(p);
  EXPECT_NE(truth_to_json(a, a.camera_to_cad, nullptr), truth_to_json(c, c.camera_to_cad, nullptr));
}

TEST(SceneGenerator, PlanListsEveryElementWithRules) {
  SceneParams p;
  p.seed = 5;
  p.cables = 3;
  const SimScene s = generate_scene(p);
  const InspectionPlan plan = scene_plan(s);
  const Scene cad = nominal_scene(s);
  for (const auto& e : cad.elements) EXPECT_NE(plan.find(e.name), nullptr) << e.name;
  int cables = 0;
  for (const auto& e : plan.elements) {
    EXPECT_GE(cad.find(e.name), 0) << e.name;
    if (e.kind != ElementKind::Cable) continue;
    ++cables;
    EXPECT_GT(e.diameter_mm, 0);
    EXPECT_GT(e.allowed_bend_radius_mm(), 0);
    EXPECT_GE(e.attached.size(), 2u);  // connectors at both ends at least
    for (const auto& a : e.attached) EXPECT_GE(cad.find(a), 0) << a;
  }
  EXPECT_EQ(cables, 3);
  // The camera looks at the cables from ~600 mm, at most 30 deg off the plate normal.
  const Eigen::Vector3d z = s.camera_to_cad.linear().col(2);
  EXPECT_LE(std::acos(-z.z()) * 180 / M_PI, 30.0 + 1e-9);
  EXPECT_NEAR((s.camera_to_cad.translation() - s.view_target).norm(), 600.0, 6.0 + 1e-9);
}
