// Whether a scan shows both surfaces of a gap: a straight cable (radius 2 mm) and a block 1 mm above it, with scan
// points placed by hand where the rule must see them, or not.
#include <gtest/gtest.h>

#include "ewis/raycast/raycaster.hpp"
#include "ewis/sim/gap_visibility.hpp"

namespace ewis::sim {
namespace {

struct Fixture {
  SimScene sim;
  Scene built;
  ScanResult scan;

  Fixture() {
    SimCable c;
    c.name = "cable_A";
    c.diameter_mm = 4.0;
    c.clearance_mm = 3.0;
    RoutePiece p;
    p.start = Eigen::Vector3d(-50, 0, 0);
    p.end = Eigen::Vector3d(50, 0, 0);
    c.as_built.pieces.push_back(p);
    c.nominal = c.as_built;
    sim.cables.push_back(c);
    SimRigid block;
    block.name = "block";
    block.solid.shapes.push_back(make_aabb_shape(Eigen::Vector3d(-5, -5, 3), Eigen::Vector3d(5, 5, 5)));
    block.foreign = true;
    sim.rigids.push_back(block);
    measure_scene(sim);
    const std::vector<Eigen::Vector3f> tri = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    add_element(built, "block", tri, {{0, 1, 2}});
    add_element(built, "cable_A", tri, {{0, 1, 2}});
  }
  void add(const Eigen::Vector3d& x, std::uint32_t element, PointKind kind = PointKind::Surface) {
    scan.cloud.points.push_back(x.cast<float>());
    scan.element.push_back(element);
    scan.kind.push_back(kind);
  }
  // The cable's flank (y = 2) along its length, every 0.5 mm between x0 and x1.
  void cable_points(double x0, double x1) {
    for (double x = x0; x <= x1 + 1e-9; x += 0.5) add({x, 2.0, 0.0}, 1);
  }
  // The block's underside at height z over y in [-0.5, 0.5] and x in [-4, 4].
  void block_points(double z, PointKind kind = PointKind::Surface) {
    for (double x = -4; x <= 4; x += 0.5)
      for (double y = -0.5; y <= 0.5; y += 0.5) add({x, y, z}, 0, kind);
  }
  const SimGap& gap() {
    mark_seen_gaps(sim, built, scan, Pose::Identity());
    for (const SimGap& g : sim.gaps)
      if (g.with == "block") return g;
    throw std::runtime_error("no gap to the block");
  }
};

TEST(GapVisibility, TheGapAndItsEnds) {
  Fixture f;
  ASSERT_EQ(f.sim.defects.size(), 1u);  // 1 mm, under the 3 mm clearance
  const SimGap& g = f.gap();
  EXPECT_NEAR(g.gap_mm, 1.0, 1e-6);
  EXPECT_NEAR(g.on_cable_surface.z(), 2.0, 1e-3);
  EXPECT_NEAR(g.on_other_surface.z(), 3.0, 1e-3);
  EXPECT_NEAR((g.on_other_surface - g.on_cable_surface).norm(), 1.0, 1e-3);
  EXPECT_NEAR(f.sim.defects[0].on_other_surface.z(), 3.0, 1e-3);
}

TEST(GapVisibility, BothSurfacesMeasuredAtTheGapAreSeen) {
  Fixture f;
  f.cable_points(-10, 10);
  f.block_points(3.0);
  const SimGap& g = f.gap();
  ASSERT_TRUE(g.seen);
  EXPECT_TRUE(*g.seen);
  ASSERT_TRUE(f.sim.defects[0].seen);
  EXPECT_TRUE(*f.sim.defects[0].seen);
}

TEST(GapVisibility, OnlyTheFarSideOfTheOtherIsNotSeen) {
  Fixture f;
  f.cable_points(-10, 10);
  f.block_points(5.0);  // the block's top: 3 mm from the cable, the gap 1 mm
  EXPECT_FALSE(*f.gap().seen);
  EXPECT_FALSE(*f.sim.defects[0].seen);
}

TEST(GapVisibility, OutliersAtTheGapAreNotASurface) {
  Fixture f;
  f.cable_points(-10, 10);
  f.block_points(3.0, PointKind::Mixed);
  EXPECT_FALSE(*f.gap().seen);
}

TEST(GapVisibility, TheCableMustBeSeenAroundTheGap) {
  Fixture f;
  f.cable_points(20, 40);  // far along the cable only
  f.block_points(3.0);
  EXPECT_FALSE(*f.gap().seen);
}

}  // namespace
}  // namespace ewis::sim
