#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>

#include "ewis/raycast/raycaster.hpp"
#include "ewis/scene/primitives.hpp"
#include "ewis/sim/sensor.hpp"

using namespace ewis;
using namespace ewis::sim;
using V3 = Eigen::Vector3d;

namespace {

void add_mesh(Scene& s, const std::string& name, const Mesh& m) { add_element(s, name, m.vertices, m.triangles); }

// The camera at the origin looking along +z (camera frame = world frame).
const Pose kIdentity = Pose::Identity();

Camera small_camera() { return Camera{320, 256, 58.0}; }

// A 100 x 160 mm step 600 mm in front of the sensor, on a wall 200 mm behind it: depth edges all round the step.
Scene step_before_wall() {
  Scene s;
  add_mesh(s, "wall", make_box(V3(-2000, -2000, 800), V3(2000, 2000, 810)));
  add_mesh(s, "step", make_box(V3(-50, -80, 600), V3(50, 80, 800)));
  return s;
}

SensorParams noise_free() {
  SensorParams p;
  p.noise_free = true;
  return p;
}

}  // namespace

TEST(Sensor, PlaneAtKnownDistanceGivesThatDepth) {
  Scene s;
  add_mesh(s, "plane", make_box(V3(-2000, -2000, 500), V3(2000, 2000, 510)));
  const Raycaster caster(s);
  const ScanResult r = scan(caster, small_camera(), kIdentity, noise_free());
  EXPECT_EQ(r.cloud.size(), std::size_t(320 * 256));  // every pixel lit, nothing grazing
  EXPECT_EQ(r.outliers, 0u);
  for (const auto& p : r.cloud.points) ASSERT_NEAR(p.z(), 500.0f, 2e-3f);
}

TEST(Sensor, PointsInSensorFrameUnderAnyPose) {
  Scene s;
  add_mesh(s, "plane", make_box(V3(-2000, -2000, -10), V3(2000, 2000, 0)));  // top at z = 0
  const Raycaster caster(s);
  const Pose cam = look_at(V3(100, 50, 600), V3(100, 50, 0), V3::UnitY());
  const ScanResult r = scan(caster, small_camera(), cam, noise_free());
  ASSERT_GT(r.cloud.size(), 10000u);
  for (const auto& p : r.cloud.points) {
    ASSERT_NEAR(p.z(), 600.0f, 2e-3f);                                  // sensor frame: depth 600
    ASSERT_NEAR((cam * p.cast<double>()).z(), 0.0, 2e-3);                // CAD frame: on the plate
  }
}

TEST(Sensor, SpherePointsLieOnTheSphere) {
  Scene s;
  const V3 c(20, -10, 600);
  add_mesh(s, "sphere", make_sphere(c, 80, 256, 128));
  const Raycaster caster(s);
  const ScanResult r = scan(caster, small_camera(), kIdentity, noise_free());
  ASSERT_GT(r.cloud.size(), 1000u);
  double worst = 0;
  for (const auto& p : r.cloud.points) worst = std::max(worst, std::abs((p.cast<double>() - c).norm() - 80.0));
  EXPECT_LT(worst, 0.05);  // tessellation sag only
  // Nothing measured beyond 75 deg of incidence: the silhouette rim is missing.
  EXPECT_GT(r.grazing, 0u);
}

TEST(Sensor, BoxOccludesWhatIsBehindIt) {
  Scene s;
  add_mesh(s, "wall", make_box(V3(-2000, -2000, 800), V3(2000, 2000, 810)));
  add_mesh(s, "box", make_box(V3(-60, -60, 400), V3(60, 60, 450)));
  const Raycaster caster(s);
  const ScanResult r = scan(caster, small_camera(), kIdentity, noise_free());
  std::size_t box_points = 0;
  for (std::size_t i = 0; i < r.cloud.size(); ++i) {
    const auto& p = r.cloud.points[i];
    const double ax = p.x() / p.z(), ay = p.y() / p.z();
    if (r.element[i] == 0) {
      // No wall point seen through the box's silhouette (60/400 rad-tangent).
      ASSERT_FALSE(std::abs(ax) < 60.0 / 400.0 - 1e-3 && std::abs(ay) < 60.0 / 400.0 - 1e-3) << ax << " " << ay;
    } else {
      ++box_points;
      ASSERT_NEAR(p.z(), 400.0f, 2e-3f);
    }
  }
  EXPECT_GT(box_points, 1000u);
}

TEST(Sensor, StereoShadowBesideAStepOnTheProjectorsOppositeSide) {
  // A step (box from the wall toward the sensor) at x in [-50, 50]; the projector sits at x = +100.
  // Projector rays to the wall at x in [-100, -50] are blocked by the step; the camera sees the wall
  // for x < -66.7 (its own occlusion), so x in [-100, -67] is seen but dark. On the +x side, lit.
  Scene s;
  add_mesh(s, "wall", make_box(V3(-2000, -2000, 800), V3(2000, 2000, 810)));
  add_mesh(s, "step", make_box(V3(-50, -2000, 600), V3(50, 2000, 800)));
  const Raycaster caster(s);
  const ScanResult r = scan(caster, small_camera(), kIdentity, noise_free());
  std::size_t left = 0, right = 0;
  for (std::size_t i = 0; i < r.cloud.size(); ++i) {
    if (r.element[i] != 0) continue;
    const double x = r.cloud.points[i].x();
    if (x > -98 && x < -70) ++left;
    if (x > 70 && x < 98) ++right;
  }
  EXPECT_EQ(left, 0u);
  EXPECT_GT(right, 500u);
  EXPECT_GT(r.shadowed, 500u);
}

TEST(Sensor, OutlierFractionAndKinds) {
  const Scene s = step_before_wall();
  const Raycaster caster(s);
  SensorParams p;
  p.outlier_fraction = 0.4;
  const ScanResult r = scan(caster, small_camera(), kIdentity, p);
  EXPECT_NEAR(double(r.outliers) / r.cloud.size(), 0.4, 0.005);
  std::size_t counts[4] = {0, 0, 0, 0};
  for (auto k : r.kind) ++counts[static_cast<int>(k)];
  EXPECT_EQ(counts[0], r.surface_points);
  EXPECT_GT(counts[1], 0u);
  EXPECT_GT(counts[2], 0u);
  EXPECT_GT(counts[3], 0u);
  // Mixed pixels lie between the step's front (600) and the wall (800).
  for (std::size_t i = 0; i < r.cloud.size(); ++i)
    if (r.kind[i] == PointKind::Mixed) {
      ASSERT_TRUE(r.cloud.points[i].z() > 600 && r.cloud.points[i].z() < 800);
    }
}

// Mismatch patches (SensorParams::mismatch_patches) move patches of surface pixels along their rays by 1-10 mm, in
// place (a pixel still gives one depth); every other surface point is the same as without them.
TEST(Sensor, MismatchPatchesMovePixelsAlongTheirRaysInPlace) {
  const Scene s = step_before_wall();
  const Raycaster caster(s);
  SensorParams p;
  p.sigma600_mm = 0.1;
  p.outlier_fraction = 0.2;
  const ScanResult plain = scan(caster, small_camera(), kIdentity, p);
  p.mismatch_patches = 200;
  const ScanResult r = scan(caster, small_camera(), kIdentity, p);
  ASSERT_EQ(r.surface_points, plain.surface_points);
  EXPECT_GT(r.mismatched, 200u * 4u / 2u);  // patches of 2-6 px a side, some overlapping
  std::size_t moved = 0;
  for (std::size_t i = 0; i < r.surface_points; ++i) {
    const Eigen::Vector3f a = plain.cloud.points[i], b = r.cloud.points[i];
    if (r.kind[i] != PointKind::Mismatch) {
      ASSERT_EQ(a, b) << i;
      continue;
    }
    ++moved;
    ASSERT_NEAR(a.normalized().dot(b.normalized()), 1.0, 1e-6);  // on the same ray
    const double offset = double(b.norm()) - double(a.norm());
    ASSERT_GE(std::abs(offset), 1.0 - 1e-3);
    ASSERT_LE(std::abs(offset), 10.0 + 1e-3);
  }
  EXPECT_EQ(moved, r.mismatched);
}

TEST(Sensor, NoiseSigmaAlongTheRay) {
  Scene s;
  add_mesh(s, "plane", make_box(V3(-2000, -2000, 600), V3(2000, 2000, 610)));
  const Raycaster caster(s);
  SensorParams p;
  p.outlier_fraction = 0.0;
  p.sigma600_mm = 0.25;
  const ScanResult r = scan(caster, small_camera(), kIdentity, p);
  double sum = 0, sum2 = 0, perp = 0;
  for (const auto& q : r.cloud.points) {
    const V3 v = q.cast<double>();
    const V3 dir = v.normalized();
    const double truth = 600.0 / dir.z();  // range to the plane along this ray
    const double sigma = 0.25 * (truth / 600.0) * (truth / 600.0);
    const double e = (v.norm() - truth) / sigma;
    sum += e;
    sum2 += e * e;
    perp = std::max(perp, 0.0);
  }
  const double n = r.cloud.size();
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.02);
  EXPECT_NEAR(sd, 1.0, 0.02);
}

TEST(Sensor, SameSeedSameBitsForAnyThreadCount) {
  Scene s;
  add_mesh(s, "wall", make_box(V3(-2000, -2000, 800), V3(2000, 2000, 810)));
  add_mesh(s, "ball", make_sphere(V3(0, 0, 600), 90));
  const Raycaster caster(s);
  SensorParams p;
  p.seed = 77;
  const ScanResult a = scan(caster, small_camera(), kIdentity, p);
  ScanResult b;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    b = scan(caster, small_camera(), kIdentity, p);
  }
  ASSERT_EQ(a.cloud.size(), b.cloud.size());
  EXPECT_EQ(0, std::memcmp(a.cloud.points.data(), b.cloud.points.data(), a.cloud.size() * sizeof(Eigen::Vector3f)));
  p.seed = 78;
  const ScanResult c = scan(caster, small_camera(), kIdentity, p);
  EXPECT_NE(0, std::memcmp(a.cloud.points.data(), c.cloud.points.data(),
                           std::min(a.cloud.size(), c.cloud.size()) * sizeof(Eigen::Vector3f)));
}
