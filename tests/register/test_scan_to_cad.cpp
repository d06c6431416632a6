// Scan-to-CAD registration on the rigid elements: from a perturbed pose, globally, with a moved cable.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstdlib>
#include <iostream>
#include <random>
#include <string>
#include <string_view>

#include "ewis/filter/outlier_removal.hpp"
#include "ewis/raycast/raycaster.hpp"
#include "ewis/register/scan_to_cad.hpp"
#include "ewis/sim/sensor.hpp"
#include "synthetic_scene.hpp"

namespace ewis {
namespace {

using test::off_at_scene;
using test::pose_error;
using test::PoseError;

CadTargetParams target_params() {
  CadTargetParams p;
  p.spacing_mm = 1.0;
  return p;
}

const CadTarget& cad_target() {
  static const CadTarget t = build_cad_target(test::make_scene(), test::make_plan(), target_params());
  return t;
}

TEST(CadTarget, SamplesOnlyRigidElementsWithNormals) {
  const Scene scene = test::make_scene();
  const CadTarget& t = cad_target();
  const int cable = scene.find("cable_A");
  ASSERT_GE(cable, 0);
  ASSERT_FALSE(t.rigid.empty());
  ASSERT_EQ(t.rigid.normals.size(), t.rigid.size());
  for (std::uint32_t e : t.rigid_element) ASSERT_NE(static_cast<int>(e), cable);
  EXPECT_FALSE(t.cables.empty());
  ASSERT_TRUE(t.cable_tree);
  // Spacing ~1 mm: about one sample per mm^2 of rigid area.
  double area = 0;
  for (const auto& e : scene.elements)
    if (e.name != "cable_A") area += e.area_mm2;
  EXPECT_NEAR(static_cast<double>(t.rigid.size()) / area, 1.0, 0.1);
}

TEST(CadTarget, ExclusionZoneAroundCable) {
  const CadTarget& t = cad_target();
  // A point on the cable's CAD surface and one 1 mm above the plate far from it.
  const Eigen::Vector3f on_cable = t.cables.points[t.cables.size() / 2];
  const std::vector<Eigen::Vector3f> pts = {on_cable, on_cable + Eigen::Vector3f(0, 0, 3.5f),
                                            Eigen::Vector3f(390, 20, 1)};
  const auto keep = points_away_from_cables(pts, Pose::Identity(), t);
  ASSERT_EQ(keep.size(), 1u);
  EXPECT_EQ(keep[0], 2u);
}

TEST(ScanToCad, FromPerturbedPoseWithMovedCable) {
  const CadTarget& t = cad_target();
  for (std::uint64_t seed = 11; seed <= 13; ++seed) {
    // As built, the cable lies 12 mm aside and 4 mm higher than in the CAD.
    const test::SimScan sim = test::simulate_scan(test::make_scene(12.0, 4.0), seed);
    const Pose init = off_at_scene(sim.camera_to_cad, seed, 10.0, 50.0);
    const ScanToCadResult r = register_scan_to_cad(sim.scan, t, init);
    const PoseError e = pose_error(r.registration.source_to_target, sim.camera_to_cad);
    SCOPED_TRACE("seed " + std::to_string(seed));
    EXPECT_TRUE(r.valid);
    EXPECT_FALSE(r.used_global);
    EXPECT_LT(e.deg, 0.1);
    EXPECT_LT(e.mm, 0.3);
    EXPECT_GT(r.excluded_near_cables, 0u);
    EXPECT_TRUE(r.registration.converged);
  }
}

// With the exact surface indexed (as inspect does it), the last step runs on it: the same scans end as close.
TEST(ScanToCad, LastStepOnTheExactSurface) {
  const Scene cad = test::make_scene();
  CadTargetParams tp = target_params();
  tp.exact_surface = true;
  const CadTarget t = build_cad_target(cad, test::make_plan(), tp);
  ASSERT_TRUE(t.surface);
  EXPECT_EQ(t.surface->elements().size(), cad.elements.size() - 1);  // every rigid element, not the cable
  for (std::uint64_t seed = 11; seed <= 11; ++seed) {
    const test::SimScan sim = test::simulate_scan(test::make_scene(12.0, 4.0), seed);
    const ScanToCadResult r = register_scan_to_cad(sim.scan, t, off_at_scene(sim.camera_to_cad, seed, 10.0, 50.0));
    const PoseError e = pose_error(r.registration.source_to_target, sim.camera_to_cad);
    SCOPED_TRACE("seed " + std::to_string(seed));
    EXPECT_TRUE(r.valid);
    EXPECT_LT(e.deg, 0.02);
    EXPECT_LT(e.mm, 0.05);
  }
}

// A cable moved by a few mm is too close for the robust kernel to ignore: as a rigid anchor it biases the
// pose; excluded (paper 4.2), it cannot.
TEST(ScanToCad, MovedCableDoesNotPullThePose) {
  const Scene cad = test::make_scene();
  const test::SimScan sim = test::simulate_scan(test::make_scene(2.0, 1.5), 21, 0.2, 0.0);
  const Pose init = off_at_scene(sim.camera_to_cad, 21, 3.0, 10.0);
  const ScanToCadResult with_plan = register_scan_to_cad(sim.scan, cad_target(), init);
  const CadTarget all_rigid = build_cad_target(cad, InspectionPlan{}, target_params());
  const ScanToCadResult no_plan = register_scan_to_cad(sim.scan, all_rigid, init);
  const PoseError e1 = pose_error(with_plan.registration.source_to_target, sim.camera_to_cad);
  const PoseError e2 = pose_error(no_plan.registration.source_to_target, sim.camera_to_cad);
  std::cout << "moved cable: excluded " << e1.deg << " deg " << e1.mm << " mm; as rigid " << e2.deg << " deg "
            << e2.mm << " mm\n";
  EXPECT_LT(e1.deg, 0.1);
  EXPECT_LT(e1.mm, 0.3);
  EXPECT_LT(e1.mm, e2.mm);
}

// A view the plate fills, with only the cable on it (no block, bracket or connector): the rigid CAD fixes the height
// and the tilt, nothing along the plate. The coarse pass matched to the cables' CAD too finds the pose along the plate
// and the turn about its normal, which the fine pass on the plate alone keeps; on the rigid elements alone the
// pose is not found (ScanToCadParams::local_retry_on_cables).
TEST(ScanToCad, ThePlateAloneInViewIsFixedByTheCable) {
  const CadTarget& t = cad_target();
  for (std::uint64_t seed = 31; seed <= 31; ++seed) {
    const test::SimScan sim = test::simulate_scan(test::make_scene(), seed, 0.2, 0.1);
    Cloud window;  // the scan's points within x 120-330, y 95-185 of the CAD
    for (const Eigen::Vector3f& p : sim.scan.points) {
      const Eigen::Vector3d q = sim.camera_to_cad * p.cast<double>();
      if (q.x() > 120 && q.x() < 330 && q.y() > 95 && q.y() < 185) window.points.push_back(p);
    }
    const Pose init = off_at_scene(sim.camera_to_cad, seed, 3.0, 10.0);
    const ScanToCadResult r = register_scan_to_cad(window, t, init);
    const PoseError e = pose_error(r.registration.source_to_target, sim.camera_to_cad);
    ScanToCadParams rigid_only;
    rigid_only.local_retry_on_cables = false;
    rigid_only.global_fallback = false;  // (which turned these views 84-180 deg: nothing but a plate to find)
    const ScanToCadResult r0 = register_scan_to_cad(window, t, init, rigid_only);
    const PoseError e0 = pose_error(r0.registration.source_to_target, sim.camera_to_cad);
    std::cout << "plate alone, seed " << seed << ": with the cables " << e.deg << " deg " << e.mm << " mm (global "
              << r.used_global << "); rigid only " << e0.deg << " deg " << e0.mm << " mm (global " << r0.used_global
              << ")\n";
    EXPECT_TRUE(r.valid);
    EXPECT_LT(e.deg, 0.1);
    EXPECT_LT(e.mm, 0.3);
    EXPECT_GT(e0.deg + e0.mm, 10.0 * (e.deg + e.mm));
  }
}

// A background the CAD does not model (a floor 150 mm under the plate, larger than the scene): with the
// initial pose, what it maps beyond the CAD's box grown by the expected error is left out. Before, on the
// second scanner's campaign with such a floor, the floor pulled the ICP 6 mm off and, matched onto the plate,
// won a global candidate 190 mm off.
TEST(ScanToCad, BackgroundBeyondTheCadIsLeftOut) {
  Scene as_built = test::make_scene();
  test::add_mesh(as_built, "floor", make_box(Eigen::Vector3d(-500, -400, -160), Eigen::Vector3d(900, 700, -150)));
  for (std::uint64_t seed = 11; seed <= 13; ++seed) {
    const test::SimScan sim = test::simulate_scan(as_built, seed);
    const Pose init = off_at_scene(sim.camera_to_cad, seed, 3.0, 20.0);
    // from the pose only (the global fallback, which the fitness of this scan's unseen-but-sampled surfaces
    // would call, is slow and not what is tested)
    ScanToCadParams params;
    params.global_fallback = false;
    ScanToCadParams no_crop = params;
    no_crop.crop_to_cad = false;
    const PoseError before =
        pose_error(register_scan_to_cad(sim.scan, cad_target(), init, no_crop).registration.source_to_target,
                   sim.camera_to_cad);
    const ScanToCadResult r = register_scan_to_cad(sim.scan, cad_target(), init, params);
    const PoseError e = pose_error(r.registration.source_to_target, sim.camera_to_cad);
    std::cout << "floor, seed " << seed << ": " << e.deg << " deg " << e.mm << " mm, fitness " << r.registration.fitness
              << " (without the crop: " << before.deg << " deg " << before.mm << " mm)\n";
    SCOPED_TRACE("seed " + std::to_string(seed));
    EXPECT_TRUE(r.valid);
    EXPECT_LT(e.deg, 0.1);
    EXPECT_LT(e.mm, 0.3);
    EXPECT_GT(before.mm, 1.0);  // the floor does pull an uncropped registration off
  }
}

// The plate scene on a floor 40 mm under it (25 mm around the plate) with two boxes beside it: a background just
// beyond the CAD, inside the crop's margin.
Scene scene_on_a_floor() {
  using V = Eigen::Vector3d;
  Scene as_built = test::make_scene();
  test::add_mesh(as_built, "floor", make_box(V(-25, -25, -45), V(425, 325, -40)));
  test::add_mesh(as_built, "box_1", make_box(V(410, 100, -40), V(440, 180, 50)));
  test::add_mesh(as_built, "box_2", make_box(V(-40, 200, -40), V(-12, 260, 35)));
  return as_built;
}

// The virtual sensor's 640 x 512 scan of `as_built` from `camera_to_scene` (its 40 % outliers included).
Cloud raw_scan(const Scene& as_built, const Pose& camera_to_scene, std::uint64_t seed) {
  const Raycaster caster(as_built);
  Camera camera;
  camera.width_px = 640;
  camera.height_px = 512;
  sim::SensorParams sp;
  sp.seed = seed;
  return sim::scan(caster, camera, camera_to_scene, sp).cloud;
}

// The inspection's first step: radius outlier removal with its derived parameters.
Cloud without_outliers(const Cloud& raw) {
  return select(raw, remove_radius_outliers(KdTree(raw.points), RadiusOutlierParams{}).kept);
}

// A registration from `init` with the stage reports watched: its result, its pose's error against `cam`, and whether
// the global search ran; printed with `label`.
struct WatchedRun {
  ScanToCadResult result;
  PoseError error;
  bool global_searched = false;
};
WatchedRun register_watched(const Cloud& scan, const Pose& init, const ScanToCadParams& params, const Pose& cam,
                            const std::string& label) {
  WatchedRun run;
  const auto watch = [&](std::string_view stage, double) {
    if (stage == "register-global") run.global_searched = true;
  };
  run.result = register_scan_to_cad(scan, cad_target(), init, params, watch);
  run.error = pose_error(run.result.registration.source_to_target, cam);
  std::cout << label << ": " << run.error.deg << " deg " << run.error.mm << " mm, fitness "
            << run.result.registration.fitness << ", global search " << run.global_searched << "\n";
  return run;
}

// A background just beyond the CAD, inside the crop's margin (a floor 40 mm under the plate, boxes beside it), scanned
// by the virtual sensor (occlusions, 40 % outliers, then the radius outlier removal; without the background the
// fitness is 0.99): the local result's fitness falls under trusted_fitness (0.76), but over the points it maps into
// the CAD's box it fits as a right pose does and puts no CAD face in front of the scan, so it is trusted without the
// global search (which, on the second scanner's campaign with such a background, ran on 28 of 30 scenes: 4.3 s
// instead of 0.5). Without that rule the global search runs, and the local pose still wins.
TEST(ScanToCad, ABackgroundJustBeyondTheCadCallsNoGlobalSearch) {
  using V = Eigen::Vector3d;
  const std::uint64_t seed = 41;
  // obliquely, as a robot's sensor looks at an assembly (straight down, the blocks' sides are not seen)
  const Pose cam = look_at(V(-40, -120, 480), V(200, 150, 0), V::UnitZ());
  const Cloud scan = without_outliers(raw_scan(scene_on_a_floor(), cam, seed));
  const Pose init = off_at_scene(cam, seed, 3.0, 20.0);
  for (const bool box_rule : {true, false}) {
    ScanToCadParams params;
    if (!box_rule) params.box_trusted_fitness = 2.0;  // never: the fitness alone decides, as before
    const WatchedRun run = register_watched(
        scan, init, params, cam, std::string("background beside the CAD") + (box_rule ? "" : " (fitness alone)"));
    const ScanToCadResult& r = run.result;
    const PoseError& e = run.error;
    const bool global_searched = run.global_searched;
    SCOPED_TRACE(box_rule ? "box rule" : "fitness alone");
    EXPECT_TRUE(r.valid);
    EXPECT_LT(e.deg, 0.1);
    EXPECT_LT(e.mm, 0.3);
    EXPECT_FALSE(r.used_global);
    if (box_rule) {
      EXPECT_LT(r.registration.fitness, params.trusted_fitness);  // the background lowers it ...
      EXPECT_FALSE(global_searched);                             // ... and the box rule trusts the pose
    } else {
      EXPECT_TRUE(global_searched);
    }
  }
}

// The same background, and wrong depths a few mm along the rays of a tenth of the pixels (a structured-light sensor's
// outliers): the radius outlier removal keeps them, by design, wherever a surface lies within its radius, and they fit
// no CAD face. Over all the box's points the right pose's fitness then falls under box_trusted_fitness and the global
// search ran (the second scanner at 45 % outliers: 28 of 30 scenes, 4 s a scene against 1.8); over the points on the
// scan's surfaces (ScanToCadParams::box_surface_only) it fits as before.
TEST(ScanToCad, OutliersNearTheSurfacesCallNoGlobalSearch) {
  using V = Eigen::Vector3d;
  const std::uint64_t seed = 41;
  const Pose cam = look_at(V(-40, -120, 480), V(200, 150, 0), V::UnitZ());
  Cloud raw = raw_scan(scene_on_a_floor(), cam, seed);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> depth_mm(3.0f, 4.5f);
  const std::size_t pixels = raw.points.size();
  for (std::size_t i = 0; i < pixels; i += 10) {
    const Eigen::Vector3f p = raw.points[i];
    const float off = (rng() & 1) ? depth_mm(rng) : -depth_mm(rng);
    raw.points.push_back(p + off * p.normalized());
  }
  const Cloud scan = without_outliers(raw);
  const Pose init = off_at_scene(cam, seed, 3.0, 20.0);
  for (const bool on_surfaces : {true, false}) {
    ScanToCadParams params;
    params.box_surface_only = on_surfaces;
    const WatchedRun run = register_watched(
        scan, init, params, cam,
        std::string("outliers near the surfaces") + (on_surfaces ? "" : " (box fitness over every point)"));
    const ScanToCadResult& r = run.result;
    const PoseError& e = run.error;
    const bool global_searched = run.global_searched;
    SCOPED_TRACE(on_surfaces ? "on the surfaces" : "every point");
    EXPECT_TRUE(r.valid);
    EXPECT_LT(e.deg, 0.1);
    EXPECT_LT(e.mm, 0.3);
    EXPECT_FALSE(r.used_global);
    EXPECT_EQ(global_searched, !on_surfaces);
  }
}

// Another simulator's outliers: 40 % of the pixels given a range off by a Gaussian 2 mm along their ray (one range a
// pixel: they replace the right one). Many lie near a surface, pass the spacing test of box_surface_only and fit no CAD
// face: the right pose's box fitness fell under box_trusted_fitness and the global search ran (bench/depth_noise.py on
// a campaign: 4.5-5.4 s a scene instead of 1.3-1.4). Counting only the points that have others at their range on
// the rays next to theirs (ScanToCadParams::box_surface_min_same) trusts it.
TEST(ScanToCad, WrongRangesAboutTheSurfacesCallNoGlobalSearch) {
  using V = Eigen::Vector3d;
  const std::uint64_t seed = 43;
  const Pose cam = look_at(V(-40, -120, 480), V(200, 150, 0), V::UnitZ());
  Cloud raw = raw_scan(scene_on_a_floor(), cam, seed);
  std::mt19937_64 rng(seed);
  std::bernoulli_distribution wrong(0.4);
  std::normal_distribution<float> off_mm(0.0f, 2.0f);
  for (Eigen::Vector3f& p : raw.points)
    if (wrong(rng)) p += off_mm(rng) * p.normalized();
  const Cloud scan = without_outliers(raw);
  const Pose init = off_at_scene(cam, seed, 3.0, 20.0);
  for (const std::size_t min_same : {std::size_t(2), std::size_t(0)}) {
    ScanToCadParams params;
    params.box_surface_min_same = min_same;
    const WatchedRun run = register_watched(scan, init, params, cam,
                                            "wrong ranges about the surfaces, min_same " + std::to_string(min_same));
    const ScanToCadResult& r = run.result;
    const PoseError& e = run.error;
    const bool global_searched = run.global_searched;
    SCOPED_TRACE(min_same > 0 ? "points with others at their range" : "the spacing test alone");
    EXPECT_TRUE(r.valid);
    EXPECT_LT(e.deg, 0.1);
    EXPECT_LT(e.mm, 0.3);
    EXPECT_EQ(global_searched, min_same == 0);
  }
}

// Boxes the CAD lacks beside it, level with the plate and taller than the scene, 15-40 mm away: inside the crop's
// margin (the pose error, 60 mm), so in the scan the registration sees. From a start 3 deg and 12 mm off, the coarse
// pass reaches 3 x 60 mm and the boxes pull its correspondences: every one of 12 virtual scans ended 1.5 deg or 3-5 mm
// off (box fitness 0.59-0.73: not trusted; the global search, off here, is what corrected it, 10 s a scene on the
// second scanner's clutter). Refined again as if the start were at most 20 mm off (ScanToCadParams::
// local_retry_near_mm), 6 of the 12 are found; two of them here.
TEST(ScanToCad, ClutterBesideTheCadIsOutreachedFromANearStart) {
  using V = Eigen::Vector3d;
  Scene as_built = test::make_scene();
  test::add_mesh(as_built, "box_1", make_box(V(415, 40, -5), V(500, 200, 120)));
  test::add_mesh(as_built, "box_2", make_box(V(100, 320, -5), V(260, 400, 140)));
  test::add_mesh(as_built, "box_3", make_box(V(-110, 60, -5), V(-25, 250, 100)));
  test::add_mesh(as_built, "box_4", make_box(V(150, -120, -5), V(330, -20, 90)));
  for (const std::uint64_t seed : {44, 46}) {
    const Pose cam = look_at(V(-40 + 10.0 * (seed % 5), -120, 520), V(200, 150, 0), V::UnitZ());
    const Cloud scan = without_outliers(raw_scan(as_built, cam, seed));
    const Pose init = off_at_scene(cam, seed, 3.0, 12.0);
    for (const double near_mm : {20.0, 0.0}) {
      ScanToCadParams params;
      params.global_fallback = false;
      params.local_retry_near_mm = near_mm;
      const ScanToCadResult r = register_scan_to_cad(scan, cad_target(), init, params);
      const PoseError e = pose_error(r.registration.source_to_target, cam);
      std::cout << "clutter beside the CAD, seed " << seed << (near_mm > 0 ? "" : " (no near retry)") << ": " << e.deg
                << " deg " << e.mm << " mm, fitness " << r.registration.fitness << ", box fitness " << r.box_fitness
                << ", in front " << r.free_space.fraction() << "\n";
      SCOPED_TRACE("seed " + std::to_string(seed) + (near_mm > 0 ? "" : ", no near retry"));
      if (near_mm > 0) {
        EXPECT_LT(e.deg, 0.1);
        EXPECT_LT(e.mm, 0.3);
        EXPECT_GE(r.box_fitness, params.box_trusted_fitness);
        EXPECT_LE(r.free_space.fraction(), params.box_trusted_in_front_fraction);
      } else {
        EXPECT_TRUE(e.deg > 0.5 || e.mm > 1.0);  // pulled off by the boxes
      }
    }
  }
}

TEST(ScanToCad, GlobalWithoutPose) {
  const CadTarget& t = cad_target();
  for (std::uint64_t seed = 31; seed <= 31; ++seed) {
    const test::SimScan sim = test::simulate_scan(test::make_scene(12.0, 4.0), seed);
    const ScanToCadResult r = register_scan_to_cad(sim.scan, t, std::nullopt);
    const PoseError e = pose_error(r.registration.source_to_target, sim.camera_to_cad);
    SCOPED_TRACE("seed " + std::to_string(seed));
    EXPECT_TRUE(r.used_global);
    EXPECT_TRUE(r.valid);
    EXPECT_LT(e.deg, 0.1);
    EXPECT_LT(e.mm, 0.3);
  }
}

// Without a pose, a background larger than the scene (the same floor) made the global search's voxel (the scan's
// diagonal / 40) twice the scene's scale: 123 deg off (seed 11) and 90 deg off (seed 12), both at a fitness that
// validated. The voxel is now sized by the smaller cloud (the CAD), and the pose found is refined again without
// the background (before that, the right pose's fitness over a scan mostly of floor was 0.12: not valid).
TEST(ScanToCad, GlobalWithoutPoseBesideABackground) {
  Scene as_built = test::make_scene();
  test::add_mesh(as_built, "floor", make_box(Eigen::Vector3d(-500, -400, -160), Eigen::Vector3d(900, 700, -150)));
  const test::SimScan sim = test::simulate_scan(as_built, 11);
  const ScanToCadResult r = register_scan_to_cad(sim.scan, cad_target(), std::nullopt);
  const PoseError e = pose_error(r.registration.source_to_target, sim.camera_to_cad);
  std::cout << "floor, no pose: " << e.deg << " deg " << e.mm << " mm, fitness " << r.registration.fitness
            << ", CAD in front of the scan " << r.free_space.fraction() << " of " << r.free_space.seen << "\n";
  EXPECT_TRUE(r.valid);
  EXPECT_GT(r.free_space.seen, 1000u);           // the free-space check ran ...
  EXPECT_LT(r.free_space.fraction(), 0.05);      // ... and the right pose leaves the CAD behind what was measured
  EXPECT_TRUE(r.used_global);
  EXPECT_LT(e.deg, 0.1);
  EXPECT_LT(e.mm, 0.3);
}

TEST(ScanToCad, GlobalDeterministicForAnyThreadCount) {
  const CadTarget& t = cad_target();
  const test::SimScan sim = test::simulate_scan(test::make_scene(), 41);
  ScanToCadParams p;  // one scale and fewer hypotheses: the same code paths, faster
  p.global.scale_factors = {1.0};
  p.global.max_iterations = 10000;
  p.global_candidates = 1;
  ScanToCadResult a, b;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    a = register_scan_to_cad(sim.scan, t, std::nullopt, p);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    b = register_scan_to_cad(sim.scan, t, std::nullopt, p);
  }
  EXPECT_TRUE(a.registration.source_to_target.matrix() == b.registration.source_to_target.matrix());
  EXPECT_EQ(a.registration.inliers, b.registration.inliers);
}

// The campaign (100 scenes, 10 deg / 50 mm off; global without a pose). Slow: run by hand with
// --gtest_also_run_disabled_tests --gtest_filter=*Campaign*.
TEST(ScanToCad, DISABLED_Campaign) {
  const CadTarget& t = cad_target();
  int local_ok = 0, global_ok = 0;
  const int n = std::getenv("EWIS_CAMPAIGN_N") ? std::atoi(std::getenv("EWIS_CAMPAIGN_N")) : 100;
  const int first = std::getenv("EWIS_CAMPAIGN_FIRST") ? std::atoi(std::getenv("EWIS_CAMPAIGN_FIRST")) : 0;
  const bool only_global = std::getenv("EWIS_CAMPAIGN_GLOBAL_ONLY") != nullptr;
  for (int i = first; i < first + n; ++i) {
    const std::uint64_t seed = 1000 + i;
    const test::SimScan sim = test::simulate_scan(test::make_scene(10.0 * std::sin(i), 3.0), seed);
    const ScanToCadResult r = only_global ? ScanToCadResult{}
                                          : register_scan_to_cad(sim.scan, t, off_at_scene(sim.camera_to_cad, seed, 10.0, 50.0));
    const PoseError e = pose_error(r.registration.source_to_target, sim.camera_to_cad);
    local_ok += e.deg <= 0.1 && e.mm <= 0.3;
    const ScanToCadResult g = register_scan_to_cad(sim.scan, t, std::nullopt);
    const PoseError eg = pose_error(g.registration.source_to_target, sim.camera_to_cad);
    global_ok += eg.deg <= 0.1 && eg.mm <= 0.3;
    std::cout << "scene " << i << " local " << e.deg << " deg " << e.mm << " mm fit " << r.registration.fitness
              << " | global " << eg.deg << " deg " << eg.mm << " mm fit " << g.registration.fitness << std::endl;
  }
  std::cout << "campaign: local " << local_ok << "/" << n << ", global " << global_ok << "/" << n << "\n";
  EXPECT_GE(local_ok, 0.98 * n);
  EXPECT_GE(global_ok, 0.95 * n);
}

}  // namespace
}  // namespace ewis
