#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "ewis/core/error.hpp"
#include "ewis/plan/viewpoint_plan.hpp"
#include "plan_scenes.hpp"
#include "test_tmp.hpp"

namespace ewis {
namespace {

using test::add_mesh;

// Three free cables, one of them partly hidden behind a bracket, plus the bracket: a small harness.
Scene harness() {
  Scene scene;
  add_mesh(scene, "cable_A", make_tube({{-150, 0, 0}, {0, 0, 0}, {150, 0, 0}}, 5.0, 16));
  add_mesh(scene, "cable_B", make_tube({{-150, 60, 0}, {0, 60, 30}, {150, 60, 0}}, 4.0, 16));
  add_mesh(scene, "cable_C", make_tube({{0, -80, -120}, {0, -80, 0}, {0, -80, 120}}, 6.0, 16));
  add_mesh(scene, "bracket", make_box(Eigen::Vector3d(-40, -100, -30), Eigen::Vector3d(40, -95, 30)));
  return scene;
}

InspectionPlan harness_plan() {
  InspectionPlan plan;
  plan.sensor.width_px = 320;
  plan.sensor.height_px = 256;
  for (const char* name : {"cable_A", "cable_B", "cable_C"}) {
    PlanElement e;
    e.name = name;
    e.kind = ElementKind::Cable;
    e.diameter_mm = 10;
    e.min_bend_radius_mm = 50;
    plan.elements.push_back(e);
  }
  PlanElement b;
  b.name = "bracket";
  plan.elements.push_back(b);
  return plan;
}

ViewpointParams quick_params() {
  ViewpointParams p;
  p.candidates.step_deg = 30;
  p.coverage.samples_per_element = 1500;
  return p;
}

TEST(Coverage, AllCablesAreCoveredByASmallSet) {
  const Scene scene = harness();
  const InspectionPlan plan = harness_plan();
  const auto elements = resolve_elements(scene, plan, {"all-cables"}, "scene.obj", "plan.json");
  ASSERT_EQ(elements.size(), 3u);
  const ViewpointPlan vp = plan_viewpoints(scene, plan.sensor, elements, quick_params());
  ASSERT_TRUE(vp.has_coverage);
  EXPECT_TRUE(vp.coverage.complete);
  ASSERT_EQ(vp.coverage.coverage.size(), 3u);
  for (double c : vp.coverage.coverage) EXPECT_GE(c, 0.9);
  const std::size_t size = vp.coverage.viewpoints.size();
  EXPECT_GE(size, std::max<std::size_t>(vp.coverage.lower_bound, 2));  // a tube needs two sides
  EXPECT_LE(size, 12u);

  // Check the coverage independently: other surface samples, other seed, seen by the chosen views.
  std::vector<Pose> views;
  for (const auto& v : vp.coverage.viewpoints)
    views.push_back(vp.elements[v.sphere].grid.candidates[v.candidate].camera_to_cad);
  const SurfaceSamples fresh = sample_elements(scene, elements, 3000, 77);
  const Raycaster caster(scene);
  const VisibilitySets sets =
      visible_samples(caster, plan.sensor.camera(), views, std::vector<bool>(views.size(), true), fresh, {});
  for (std::size_t k = 0; k < elements.size(); ++k) {
    std::vector<std::uint64_t> any(sets.words, 0);
    for (const auto& bits : sets.seen)
      for (std::size_t w = 0; w < sets.words; ++w) any[w] |= bits[w];
    std::size_t seen = 0;
    for (std::size_t w = sets.element_word_begin[k]; w < sets.element_word_begin[k + 1]; ++w) seen += std::popcount(any[w]);
    EXPECT_GE(double(seen) / double(sets.element_samples[k]), 0.88) << scene.elements[elements[k]].name;
  }
}

TEST(Coverage, GreedyCoverOnAKnownInstance) {
  // Two elements of 64 samples; view 0 sees all of element 0, views 1 and 2 each half of element 1,
  // view 3 sees 3/4 of both.
  VisibilitySets sets;
  sets.words = 2;
  sets.element_word_begin = {0, 1, 2};
  sets.element_samples = {64, 64};
  sets.seen = {{~0ull, 0}, {0, 0x00000000FFFFFFFFull}, {0, 0xFFFFFFFF00000000ull}, {0x0000FFFFFFFFFFFFull, 0x0000FFFFFFFFFFFFull}};
  const CoverResult r = greedy_cover(sets, 0.9);
  ASSERT_TRUE(r.complete);
  // Greedy: view 3 (96 new), then views 0 and 2 (10 still needed each); the optimum is 3 as well.
  ASSERT_EQ(r.chosen.size(), 3u);
  EXPECT_EQ(r.chosen[0], 3u);
  EXPECT_EQ(r.chosen[1], 0u);  // tie with view 2: candidate order
  EXPECT_EQ(r.chosen[2], 2u);
  EXPECT_GE(r.coverage[0], 0.9);
  EXPECT_GE(r.coverage[1], 0.9);
  EXPECT_EQ(r.lower_bound, 2u);  // element 1 needs 58 samples, no view sees more than 48
  // Half of element 1 is hidden from every view: greedy takes what can be seen and reports it.
  sets.seen = {{~0ull, 0}, {0, 0x00000000FFFFFFFFull}, {0, 0x000000000000FFFFull}};
  const CoverResult part = greedy_cover(sets, 0.9);
  EXPECT_FALSE(part.complete);
  EXPECT_EQ(part.chosen, (std::vector<std::size_t>{0, 1}));
  EXPECT_DOUBLE_EQ(part.reachable[1], 0.5);
  EXPECT_DOUBLE_EQ(part.coverage[1], 0.5);
  // An unreachable target stops without looping.
  sets.seen = {{0, 0}};
  const CoverResult none = greedy_cover(sets, 0.9);
  EXPECT_FALSE(none.complete);
  EXPECT_TRUE(none.chosen.empty());
}

TEST(Coverage, UnknownElementIsAnInputErrorNamingIt) {
  const Scene scene = harness();
  const InspectionPlan plan = harness_plan();
  try {
    resolve_elements(scene, plan, {"cable_A", "cable_Z"}, "scene.obj", "plan.json");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cable_Z"), std::string::npos);
    EXPECT_EQ(e.file(), "scene.obj");
  }
  InspectionPlan rigid_only;
  EXPECT_THROW(resolve_elements(scene, rigid_only, {"all-cables"}, "scene.obj", "plan.json"), InputError);
  const auto dup = resolve_elements(scene, plan, {"cable_B", "cable_B", "cable_A"}, "s", "p");
  EXPECT_EQ(dup, (std::vector<std::uint32_t>{1, 0}));
}

TEST(Viewpoints, JsonFollowsTheContractAndDoesNotDependOnThreads) {
  const Scene scene = harness();
  const InspectionPlan plan = harness_plan();
  ViewpointParams p;  // the default 10-degree sphere
  p.top = 4;
  std::string one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = viewpoints_json(plan_viewpoints(scene, plan.sensor, {0}, p));
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = viewpoints_json(plan_viewpoints(scene, plan.sensor, {0}, p));
  }
  EXPECT_EQ(one, two);
  const auto j = nlohmann::json::parse(one);
  EXPECT_EQ(j["element"], "cable_A");
  EXPECT_EQ(j["candidates"], 648);
  ASSERT_EQ(j["best"].size(), 4u);
  std::int64_t last = std::numeric_limits<std::int64_t>::max();
  for (std::size_t i = 0; i < 4; ++i) {
    const auto& b = j["best"][i];
    EXPECT_EQ(b["rank"], i + 1);
    EXPECT_EQ(b["position"].size(), 3u);
    EXPECT_EQ(b["target"].size(), 3u);
    ASSERT_EQ(b["camera_to_cad"].size(), 4u);
    EXPECT_EQ(b["camera_to_cad"][3], nlohmann::json::array({0.0, 0.0, 0.0, 1.0}));
    EXPECT_EQ(b["camera_to_cad"][0][3], b["position"][0]);
    const std::int64_t s = b["score_px"];
    EXPECT_LE(s, last);
    last = s;
    EXPECT_GT(s, 0);
    EXPECT_GE(b["visible_fraction"].get<double>(), 0.0);
    EXPECT_LE(b["visible_fraction"].get<double>(), 1.0);
  }
  // A straight cable along x is seen best broadside: the view direction nearly perpendicular to x.
  const auto& b0 = j["best"][0];
  const double dx = b0["position"][0].get<double>() - b0["target"][0].get<double>();
  EXPECT_LT(std::abs(dx) / 600.0, std::sin(25 * M_PI / 180)) << b0.dump();
}

TEST(Viewpoints, WritesJsonAndPictures) {
  const Scene scene = harness();
  const InspectionPlan plan = harness_plan();
  ViewpointParams p = quick_params();
  p.top = 2;
  const ViewpointPlan vp = plan_viewpoints(scene, plan.sensor, {0, 2}, p);
  const std::filesystem::path dir = ewis::test::own_tmp_dir("plan_outputs");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_viewpoint_outputs(scene, vp, dir.string());
  for (const char* f : {"viewpoints.json", "view_1.png", "view_2.png", "heatmap.png", "heatmap_cable_A.png",
                        "heatmap_cable_C.png", "cover_1.png"})
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  std::ifstream in(dir / "viewpoints.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["element"], "cable_A,cable_C");
  EXPECT_EQ(j["candidates"], 2 * 72);
  EXPECT_EQ(j["best"].size(), 2u);
  EXPECT_TRUE(j["coverage_set"]["complete"].get<bool>());
  EXPECT_EQ(j["coverage_set"]["elements"].size(), 2u);
}

}  // namespace
}  // namespace ewis
