// Campaign evaluation: report.json against truth.json on hand-made pairs with known outcomes.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "ewis/core/error.hpp"
#include "ewis/report/evaluation.hpp"
#include "report_fixture.hpp"

namespace ewis {
namespace {

using nlohmann::json;

json cable(const std::string& name, bool bend_ok, json radius, const std::vector<json>& interferences = {}) {
  return {{"name", name},          {"kind", "cable"},        {"found", true},
          {"diameter_mm", 10.0},   {"length_mm", 400.0},     {"min_bend_radius_mm", radius},
          {"min_bend_location", nullptr}, {"bend_ok", bend_ok}, {"interferences", json(interferences)},
          {"clearance_ok", interferences.empty()}, {"segments", json::array()}};
}
json inter(json with, double d) { return {{"with", with}, {"min_distance_mm", d}, {"points", 50}, {"center", {0, 0, 0}}}; }
std::string report(const std::string& verdict, const std::vector<json>& elements) {
  return json{{"verdict", verdict}, {"registration", {{"transform", json::array()}, {"rmse_mm", 0.2}, {"converged", true}}},
              {"elements", json(elements)}}.dump();
}
json truth_cable(const std::string& name, json radius) {
  return {{"name", name}, {"diameter_mm", 10.0}, {"min_bend_radius_mm", radius}, {"centerline", {{0, 0, 0}, {0, 0, 1}}}};
}
std::string truth(const std::vector<json>& cables, const std::vector<json>& defects) {
  return json{{"camera_to_cad", json::array()}, {"cables", json(cables)}, {"defects", json(defects)}}.dump();
}

TEST(CompareWithTruth, VerdictOutcomes) {
  const std::string clean = truth({truth_cable("cable_A", 60.0)}, {});
  const std::string bent = truth({truth_cable("cable_A", 40.0)},
                                 {{{"kind", "bend"}, {"element", "cable_A"}, {"radius_mm", 40.0}}});
  EXPECT_EQ(compare_with_truth(report("pass", {cable("cable_A", true, 61.2)}), clean, "s").outcome, VerdictOutcome::Correct);
  EXPECT_EQ(compare_with_truth(report("fail", {cable("cable_A", false, 30.0)}), clean, "s").outcome,
            VerdictOutcome::FalseAlarm);
  EXPECT_EQ(compare_with_truth(report("pass", {cable("cable_A", true, 61.0)}), bent, "s").outcome, VerdictOutcome::Missed);
  const SceneEvaluation ok = compare_with_truth(report("fail", {cable("cable_A", false, 41.0)}), bent, "s");
  EXPECT_EQ(ok.outcome, VerdictOutcome::Correct);
  ASSERT_EQ(ok.defects.size(), 1u);
  EXPECT_TRUE(ok.defects[0].found);
  ASSERT_EQ(ok.bends.size(), 1u);
  EXPECT_NEAR(*ok.bends[0].error_pct, 2.5, 1e-9);  // (41 - 40) / 40
}

TEST(CompareWithTruth, BendFoundOnlyOnTheRightElement) {
  const std::string t = truth({truth_cable("cable_A", 40.0), truth_cable("cable_B", nullptr)},
                              {{{"kind", "bend"}, {"element", "cable_A"}, {"radius_mm", 40.0}}});
  const SceneEvaluation e =
      compare_with_truth(report("fail", {cable("cable_A", true, 44.0), cable("cable_B", false, 20.0)}), t, "s");
  EXPECT_EQ(e.outcome, VerdictOutcome::Correct);  // the verdict is right ...
  EXPECT_FALSE(e.defects[0].found);               // ... but the defect is flagged on the wrong cable
  ASSERT_EQ(e.bends.size(), 1u);                  // cable_B is straight in truth: not compared
  EXPECT_EQ(e.bends[0].cable, "cable_A");
  EXPECT_NEAR(*e.bends[0].error_pct, 10.0, 1e-9);
}

TEST(CompareWithTruth, ClearanceNeedsTheRightWith) {
  const std::vector<json> defects = {{{"kind", "clearance"}, {"element", "cable_A"}, {"with", "pipe_1"}, {"gap_mm", 1.0}}};
  const std::string t = truth({truth_cable("cable_A", nullptr)}, defects);
  const SceneEvaluation right = compare_with_truth(
      report("fail", {cable("cable_A", true, nullptr, {inter("bracket_1", 0.2), inter("pipe_1", 1.3), inter("pipe_1", 1.1)})}), t, "s");
  ASSERT_TRUE(right.defects[0].found);
  EXPECT_NEAR(*right.defects[0].measured_gap_mm, 1.1, 1e-12);  // the closest matching one
  EXPECT_NEAR(*right.defects[0].truth_gap_mm, 1.0, 1e-12);
  EXPECT_TRUE(right.bends.empty());
  const SceneEvaluation wrong = compare_with_truth(report("fail", {cable("cable_A", true, nullptr, {inter("bracket_1", 1.0)})}), t, "s");
  EXPECT_FALSE(wrong.defects[0].found);
  EXPECT_FALSE(wrong.defects[0].measured_gap_mm);
  const SceneEvaluation foreign = compare_with_truth(report("fail", {cable("cable_A", true, nullptr, {inter(nullptr, 1.0)})}), t, "s");
  EXPECT_FALSE(foreign.defects[0].found);
}

TEST(CompareWithTruth, CableToCableMayBeReportedOnEitherCable) {
  const std::vector<json> defects = {{{"kind", "clearance"}, {"element", "cable_A"}, {"with", "cable_B"}, {"gap_mm", 0.8}}};
  const std::string t = truth({truth_cable("cable_A", nullptr), truth_cable("cable_B", nullptr)}, defects);
  const SceneEvaluation e = compare_with_truth(
      report("fail", {cable("cable_A", true, nullptr), cable("cable_B", true, nullptr, {inter("cable_A", 0.9)})}), t, "s");
  ASSERT_TRUE(e.defects[0].found);
  EXPECT_NEAR(*e.defects[0].measured_gap_mm, 0.9, 1e-12);
}

TEST(CompareWithTruth, ForeignObjectIsAnInterferenceWithNull) {
  const std::vector<json> defects = {{{"kind", "foreign_object"}, {"element", "cable_A"}, {"with", nullptr}, {"gap_mm", 0.5}}};
  const std::string t = truth({truth_cable("cable_A", nullptr)}, defects);
  const SceneEvaluation named = compare_with_truth(report("fail", {cable("cable_A", true, nullptr, {inter("pipe_1", 0.5)})}), t, "s");
  EXPECT_FALSE(named.defects[0].found);
  const SceneEvaluation found = compare_with_truth(
      report("fail", {cable("cable_A", true, nullptr, {inter("pipe_1", 0.1), inter(nullptr, 0.7)})}), t, "s");
  ASSERT_TRUE(found.defects[0].found);
  EXPECT_NEAR(*found.defects[0].measured_gap_mm, 0.7, 1e-12);
  EXPECT_FALSE(found.defects[0].with);
}

// With the truth's `location` (the gap's spot on the cable), only an entry near it finds the object: a clump of
// noise 70 mm along the cable does not (its closest_on_other and centre both far).
TEST(CompareWithTruth, AForeignObjectIsFoundByAnEntryNearIt) {
  const std::vector<json> defects = {{{"kind", "foreign_object"}, {"element", "cable_A"}, {"with", nullptr},
                                      {"gap_mm", 3.3}, {"location", {10.0, 0.0, 0.0}}}};
  const std::string t = truth({truth_cable("cable_A", nullptr)}, defects);
  const auto at = [](json f, double x_other, double x_centre) {
    f["closest_on_other"] = {x_other, 5.0, 0.0};
    f["center"] = {x_centre, 8.0, 0.0};
    return f;
  };
  const json clump = at(inter(nullptr, 7.8), 80.0, 82.0), object = at(inter(nullptr, 7.3), 12.0, 14.0);
  const SceneEvaluation far = compare_with_truth(report("fail", {cable("cable_A", true, nullptr, {clump})}), t, "s");
  EXPECT_FALSE(far.defects[0].found);
  EXPECT_EQ(far.outcome, VerdictOutcome::Correct);  // the verdict is right, the object not found
  const SceneEvaluation near =
      compare_with_truth(report("fail", {cable("cable_A", true, nullptr, {clump, object})}), t, "s");
  ASSERT_TRUE(near.defects[0].found);
  EXPECT_NEAR(*near.defects[0].measured_gap_mm, 7.3, 1e-12);  // the near entry's gap, not the clump's
  // Its centre alone near enough (a long object whose nearest point lies at its end) finds it too.
  const json long_one = at(inter(nullptr, 2.0), 50.0, 30.0);
  const SceneEvaluation by_centre =
      compare_with_truth(report("fail", {cable("cable_A", true, nullptr, {long_one})}), t, "s");
  EXPECT_TRUE(by_centre.defects[0].found);
}

TEST(CompareWithTruth, MissingRadiusAndUnknownKinds) {
  const std::vector<json> defects = {{{"kind", "missing_clamp"}, {"element", "cable_A"}}};
  const std::string t = truth({truth_cable("cable_A", 50.0)}, defects);
  json c = cable("cable_A", true, nullptr);
  c["found"] = false;
  const SceneEvaluation e = compare_with_truth(report("fail", {c}), t, "s");
  EXPECT_TRUE(e.defects[0].found);  // another kind: any failed check on the element
  ASSERT_EQ(e.bends.size(), 1u);
  EXPECT_FALSE(e.bends[0].measured_mm);
  EXPECT_FALSE(e.bends[0].error_pct);
}

TEST(CompareWithTruth, MalformedInputsThrowNamingTheFile) {
  const std::string t = truth({truth_cable("cable_A", 50.0)}, {});
  try {
    compare_with_truth("{not json", t, "s", "r.json", "t.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "r.json");
  }
  EXPECT_THROW(compare_with_truth(report("maybe", {}), t, "s"), InputError);
  EXPECT_THROW(compare_with_truth(report("pass", {}), "{\"cables\": []}", "s"), InputError);
}

TEST(ErrorStats, QuantilesAndEmpty) {
  const ErrorStats none = error_stats({});
  EXPECT_EQ(none.count, 0u);
  EXPECT_FALSE(none.median);
  EXPECT_FALSE(none.max);
  const ErrorStats s = error_stats({5, 1, 4, 2, 3});
  EXPECT_DOUBLE_EQ(*s.median, 3.0);
  EXPECT_DOUBLE_EQ(*s.p95, 4.8);  // numpy.percentile([1..5], 95)
  EXPECT_DOUBLE_EQ(*s.max, 5.0);
  EXPECT_DOUBLE_EQ(*error_stats({2.0}).p95, 2.0);
}

std::vector<SceneEvaluation> sample_scenes() {
  const std::string clean = truth({truth_cable("cable_A", 60.0)}, {});
  const std::string bent = truth({truth_cable("cable_A", 40.0)}, {{{"kind", "bend"}, {"element", "cable_A"}}});
  const std::string near = truth({truth_cable("cable_A", nullptr)},
                                 {{{"kind", "clearance"}, {"element", "cable_A"}, {"with", "pipe_1"}, {"gap_mm", 1.0}}});
  std::vector<SceneEvaluation> v;
  v.push_back(compare_with_truth(report("pass", {cable("cable_A", true, 63.0)}), clean, "scene_000"));    // +5 %
  v.push_back(compare_with_truth(report("fail", {cable("cable_A", false, 39.0)}), bent, "scene_001"));    // -2.5 %
  v.push_back(compare_with_truth(report("fail", {cable("cable_A", false, 30.0)}), clean, "scene_002"));   // false alarm, -50 %
  v.push_back(compare_with_truth(report("pass", {cable("cable_A", true, nullptr)}), near, "scene_003"));  // missed
  v.push_back(compare_with_truth(report("fail", {cable("cable_A", true, nullptr, {inter("pipe_1", 1.25)})}), near, "scene_004"));
  SceneEvaluation failed;
  failed.scene = "scene_005";
  failed.error = "registration failed";
  v.push_back(failed);
  for (std::size_t i = 0; i < v.size(); ++i) v[i].seconds = 1.0 + double(i);
  return v;
}

TEST(Summary, CountsAndStatistics) {
  const std::vector<SceneEvaluation> scenes = sample_scenes();
  const EvaluationSummary s = summarize(scenes);
  EXPECT_EQ(s.scenes, 6u);
  EXPECT_EQ(s.failed_runs, 1u);
  EXPECT_EQ(s.correct, 3u);
  EXPECT_EQ(s.false_alarms, 1u);
  EXPECT_EQ(s.missed, 1u);
  EXPECT_EQ(s.clean_scenes, 2u);
  EXPECT_EQ(s.defect_scenes, 3u);
  EXPECT_EQ(s.defects.at("bend").present, 1u);
  EXPECT_EQ(s.defects.at("bend").found, 1u);
  EXPECT_EQ(s.defects.at("clearance").present, 2u);
  EXPECT_EQ(s.defects.at("clearance").found, 1u);
  EXPECT_EQ(s.defects.at("foreign_object").present, 0u);
  EXPECT_EQ(s.bend_radius_error_pct.count, 3u);
  EXPECT_DOUBLE_EQ(*s.bend_radius_error_pct.median, 5.0);
  EXPECT_DOUBLE_EQ(*s.bend_radius_error_pct.max, 50.0);
  EXPECT_EQ(s.gap_error_mm.count, 1u);
  EXPECT_NEAR(*s.gap_error_mm.max, 0.25, 1e-12);
  EXPECT_EQ(s.seconds_per_scene.count, 5u);
  EXPECT_DOUBLE_EQ(*s.seconds_per_scene.max, 5.0);
}

// The gap goal is over the gaps whose both surfaces were seen (the truth's `seen`): a foreign object whose
// near side is hidden is read wide (an upper bound) and counts in the overall figure only.
TEST(Summary, GapErrorWhereBothSurfacesAreSeen) {
  const auto defect = [](double gap, json seen) {
    json d = {{"kind", "foreign_object"}, {"element", "cable_A"}, {"with", nullptr}, {"gap_mm", gap}};
    if (!seen.is_null()) d["seen"] = seen;
    return d;
  };
  std::vector<SceneEvaluation> v;
  v.push_back(compare_with_truth(report("fail", {cable("cable_A", true, nullptr, {inter(nullptr, 1.3)})}),
                                 truth({truth_cable("cable_A", nullptr)}, {defect(1.0, true)}), "seen_0.3"));
  v.push_back(compare_with_truth(report("fail", {cable("cable_A", true, nullptr, {inter(nullptr, 2.8)})}),
                                 truth({truth_cable("cable_A", nullptr)}, {defect(2.0, true)}), "seen_0.8"));
  v.push_back(compare_with_truth(report("fail", {cable("cable_A", true, nullptr, {inter(nullptr, 6.0)})}),
                                 truth({truth_cable("cable_A", nullptr)}, {defect(0.0, false)}), "hidden_6"));
  v.push_back(compare_with_truth(report("fail", {cable("cable_A", true, nullptr, {inter(nullptr, 1.1)})}),
                                 truth({truth_cable("cable_A", nullptr)}, {defect(1.0, nullptr)}), "unknown_0.1"));
  ASSERT_TRUE(v[0].defects[0].truth_gap_seen && *v[0].defects[0].truth_gap_seen);
  ASSERT_FALSE(v[3].defects[0].truth_gap_seen);
  const EvaluationSummary s = summarize(v);
  EXPECT_EQ(s.gap_error_mm.count, 4u);
  EXPECT_NEAR(*s.gap_error_mm.max, 6.0, 1e-12);
  EXPECT_EQ(s.gap_error_seen.stats.count, 2u);
  EXPECT_NEAR(*s.gap_error_seen.stats.max, 0.8, 1e-12);
  EXPECT_EQ(s.gap_error_seen.within_goal, 1u);
  ASSERT_EQ(s.gap_error_by_kind.count("foreign_object"), 1u);
  EXPECT_EQ(s.gap_error_by_kind.at("foreign_object").stats.count, 4u);
  EXPECT_EQ(s.gap_error_by_kind.at("foreign_object").within_goal, 2u);  // 0.3 and 0.1
  const json j = json::parse(evaluation_to_json(s, v));
  EXPECT_EQ(j["gap_error_seen_mm"]["count"], 2);
  EXPECT_EQ(j["gap_error_seen_mm"]["within_0_5_mm"], 1);
  EXPECT_EQ(j["gap_error_by_kind_mm"]["foreign_object"]["within_0_5_mm"], 2);
  EXPECT_EQ(j["scene_results"][2]["defects"][0]["truth_gap_seen"], false);
  EXPECT_NE(evaluation_to_markdown(s, v, "C").find("both surfaces are seen"), std::string::npos);
}

TEST(Summary, JsonHasTheContractFieldsAndValidates) {
  const std::vector<SceneEvaluation> scenes = sample_scenes();
  const std::string text = evaluation_to_json(summarize(scenes), scenes);
  const json j = json::parse(text);
  EXPECT_EQ(j["scenes"], 6);
  EXPECT_EQ(j["failed_runs"], 1);
  EXPECT_EQ(j["verdicts"]["false_alarms"], 1);
  EXPECT_EQ(j["defects"]["clearance"]["found"], 1);
  EXPECT_EQ(j["gap_error_mm"]["median"], 0.25);
  EXPECT_TRUE(j["seconds_per_scene"]["median"].is_number());
  EXPECT_EQ(j["scene_results"].size(), 6u);
  // Nothing to compare: statistics are null.
  const std::string empty = evaluation_to_json(summarize({}), {});
  EXPECT_TRUE(json::parse(empty)["bend_radius_error_pct"]["median"].is_null());

  // Against the contract's schema (Debian's python3-jsonschema), when available.
  const std::string schema = std::string(EWIS_REALDATA_DIR) + "/../schemas/evaluation.schema.json";
  if (!std::filesystem::exists(schema) || std::system("python3 -c 'import jsonschema' > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "schema or python3-jsonschema absent: schema validation skipped";
  const std::string dir = test::test_dir("eval_schema");
  for (const auto& [name, body] : {std::pair<std::string, std::string>{"full.json", text}, {"empty.json", empty}}) {
    std::ofstream(dir + "/" + name) << body;
    const std::string cmd = "python3 -c \"import json,sys,jsonschema; jsonschema.validate(json.load(open(sys.argv[1])), "
                            "json.load(open(sys.argv[2])))\" " + dir + "/" + name + " " + schema;
    EXPECT_EQ(std::system(cmd.c_str()), 0) << name;
  }
}

TEST(Summary, MarkdownTables) {
  const std::vector<SceneEvaluation> scenes = sample_scenes();
  const std::string md = evaluation_to_markdown(summarize(scenes), scenes, "camp");
  EXPECT_NE(md.find("| correct verdicts | 3 of 5"), std::string::npos);
  EXPECT_NE(md.find("| clearance | 2 | 1 | 50.0 % |"), std::string::npos);
  EXPECT_NE(md.find("| scene_002 | fail | pass | **false alarm** |"), std::string::npos);
  EXPECT_NE(md.find("| scene_003 | pass | fail | **missed** |"), std::string::npos);
  EXPECT_NE(md.find("## Failed runs"), std::string::npos);
  EXPECT_NE(md.find("| scene_005 | registration failed |"), std::string::npos);
}

// The 3-20 diameter band counts bends within 5 %, and within 5 % or 2 of the report's own standard errors.
TEST(Summary, BendBandWithStandardErrors) {
  const std::string bent = truth({truth_cable("cable_A", 40.0)}, {});  // 4 diameters
  auto with_se = [&](double radius, std::optional<double> se) {
    json c = cable("cable_A", true, radius);
    if (se) c["min_bend_radius_se_mm"] = *se;
    return compare_with_truth(report("pass", {c}), bent, "s");
  };
  std::vector<SceneEvaluation> v = {with_se(41.0, std::nullopt), with_se(43.2, 2.0), with_se(43.2, 1.0),
                                    with_se(43.2, std::nullopt)};
  ASSERT_TRUE(v[1].bends[0].measured_se_mm);
  EXPECT_DOUBLE_EQ(*v[1].bends[0].measured_se_mm, 2.0);
  EXPECT_FALSE(v[0].bends[0].measured_se_mm);
  const json j = json::parse(evaluation_to_json(summarize(v), v));
  const json& band = j["bend_radius_error_pct_3_to_20_diameters"];
  EXPECT_EQ(band["count"], 4);
  EXPECT_EQ(band["within_5_pct"], 1);         // +2.5 %
  EXPECT_EQ(band["within_5_pct_or_2_se"], 2);  // and +8 % = 3.2 mm, under 2 x 2.0 mm
  EXPECT_EQ(j["scene_results"][1]["bends"][0]["measured_se_mm"], 2.0);
  const std::string md = evaluation_to_markdown(summarize(v), v, "camp");
  EXPECT_NE(md.find("within 5 % or 2 reported standard errors) | 1 of 4 (2) |"), std::string::npos);
}

TEST(EvaluateCampaign, FailedRunsAreCountedAndTheCampaignGoesOn) {
  const std::string dir = test::test_dir("campaign");
  const std::string camp = dir + "/camp";
  auto scene = [&](const std::string& name, bool complete) {
    std::filesystem::create_directories(camp + "/" + name);
    for (const char* f : {"scene.obj", "plan.json", "scan.ply", "pose.txt", "truth.json"})
      if (complete || std::string(f) != "truth.json") std::ofstream(camp + "/" + name + "/" + f) << "broken\n";
  };
  scene("scene_001", true);
  scene("scene_000", true);
  scene("scene_002", false);  // no truth.json: not a scene
  std::filesystem::create_directories(camp + "/notes");
  EXPECT_EQ(campaign_scenes(camp), (std::vector<std::string>{"scene_000", "scene_001"}));
  // Without pose.txt a folder is a scene only for an evaluation that registers without poses (--no-pose).
  scene("scene_003", true);
  std::filesystem::remove(camp + "/scene_003/pose.txt");
  EXPECT_EQ(campaign_scenes(camp), (std::vector<std::string>{"scene_000", "scene_001"}));
  EXPECT_EQ(campaign_scenes(camp, false), (std::vector<std::string>{"scene_000", "scene_001", "scene_003"}));
  std::filesystem::remove_all(camp + "/scene_003");
  std::vector<std::string> seen;
  EvaluateParams p;
  p.on_scene = [&](std::size_t i, std::size_t n, const SceneEvaluation& e) {
    EXPECT_EQ(n, 2u);
    seen.push_back(e.scene);
  };
  const CampaignEvaluation ev = evaluate_campaign(camp, dir + "/out", p);
  EXPECT_EQ(seen, (std::vector<std::string>{"scene_000", "scene_001"}));
  EXPECT_EQ(ev.summary.scenes, 2u);
  EXPECT_EQ(ev.summary.failed_runs, 2u);
  EXPECT_FALSE(ev.scenes[0].error.empty());
  EXPECT_TRUE(std::filesystem::exists(dir + "/out/evaluation.json"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/out/evaluation.md"));
  const json j = json::parse(std::ifstream(dir + "/out/evaluation.json"));
  EXPECT_EQ(j["failed_runs"], 2);
  EXPECT_TRUE(j["seconds_per_scene"]["median"].is_null());
  EXPECT_THROW(evaluate_campaign(dir + "/nothing", dir + "/out2"), InputError);
  EXPECT_THROW(evaluate_campaign(camp + "/notes", dir + "/out2"), InputError);
}

}  // namespace
}  // namespace ewis
