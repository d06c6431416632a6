#pragma once
// Campaign evaluation (issue 6, item 4; CONTRACT.md "ewis evaluate"): the paper's 140-cloud experiment as a
// function. Each scene's report.json is compared with its truth.json:
//  - verdict: correct, false alarm (fail on a scene whose truth has no defect), missed (pass with defects);
//  - per defect of the truth: found when the report flags it on the right element:
//      bend            bend_ok == false on `element`;
//      clearance       an interference on `element` whose `with` is the truth's `with` (when `with` is another
//                      cable, the same interference reported on that cable towards `element` counts too: it
//                      is one gap between two cables);
//      foreign_object  an interference on `element` with `with` null and, where the truth defect has a
//                      `location`, its closest_on_other or center within 30 mm of it;
//      other kinds     `element` not found, or bend_ok or clearance_ok false;
//  - bend radius error % = |report min_bend_radius_mm - truth| / truth x 100, for each truth cable whose
//    min_bend_radius_mm is not null and whose report value is not null (a null report value is counted apart);
//  - gap error mm = |interference min_distance_mm - truth gap_mm| for found clearance / foreign defects (the
//    matching interference with the smallest distance); apart, over the defects whose truth says `"seen": true`
//    (both surfaces measured at the gap: ewis simulate's gap_visibility.hpp), the issue's goal "within 0.5 mm where
//    both surfaces are seen"; a truth without `seen` counts in the first figure only.
// Statistics (median, p95, max) are null where there is nothing to compare.
#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ewis/core/progress.hpp"
#include "ewis/report/run_inspection.hpp"

namespace ewis {

struct DefectCheck {
  std::string kind, element;
  std::optional<std::string> with;
  bool found = false;
  std::optional<double> truth_gap_mm, measured_gap_mm;   // clearance / foreign_object
  std::optional<bool> truth_gap_seen;                    // the truth's `seen` (both surfaces measured), when given
  std::optional<double> truth_radius_mm;                 // bend
};

struct BendCheck {
  std::string cable;
  double truth_mm = 0.0;
  double truth_diameter_mm = 0.0;
  std::optional<double> measured_mm;                     // nullopt: the report has no radius (or no cable)
  std::optional<double> error_pct;                       // signed: (measured - truth) / truth x 100
  std::optional<double> measured_se_mm;                  // the report's min_bend_radius_se_mm, when given
  bool measured_is_bound = false;                        // the report's min_bend_radius_is_bound (an upper bound)
};

enum class VerdictOutcome { Correct, FalseAlarm, Missed, NotRun };
const char* verdict_outcome_name(VerdictOutcome outcome);

struct SceneEvaluation {
  std::string scene;                    // sub-folder name
  bool ran = false;                     // false: the inspection (or reading its truth) threw
  std::string error;                    // why it did not run
  std::string verdict;                  // "pass" / "fail" of the report ("" when not run)
  bool truth_has_defects = false;
  VerdictOutcome outcome = VerdictOutcome::NotRun;
  std::vector<DefectCheck> defects;
  std::vector<BendCheck> bends;
  // Registration (issue 4): the report's transform against the truth's camera_to_cad: the rotation angle of
  // their difference, and the largest displacement it causes at the truth's cable centreline points (the
  // scene's points). nullopt when either side lacks the transform.
  std::optional<double> registration_rotation_deg, registration_error_mm;
  double seconds = 0.0;                 // wall time of the inspection (load + inspect + write)
};

// Compares one report.json text with one truth.json text. Throws InputError(report_path or truth_path, ...)
// when either is malformed (not JSON, missing verdict/elements/defects...).
SceneEvaluation compare_with_truth(const std::string& report_json, const std::string& truth_json,
                                   const std::string& scene_name, const std::string& report_path = "report.json",
                                   const std::string& truth_path = "truth.json");

struct ErrorStats {
  std::size_t count = 0;
  std::optional<double> median, p95, max;  // nullopt when count == 0
};
// Median and p95 by linear interpolation between order statistics (numpy's default).
ErrorStats error_stats(std::vector<double> values);

// Absolute gap errors and how many of them are within the 0.5 mm.
struct GapErrors {
  ErrorStats stats;
  std::size_t within_goal = 0;
};

struct DefectTally {
  std::size_t present = 0, found = 0;
};

struct EvaluationSummary {
  std::size_t scenes = 0, failed_runs = 0;
  std::size_t correct = 0, false_alarms = 0, missed = 0;
  std::size_t clean_scenes = 0, defect_scenes = 0;       // among the scenes that ran
  std::map<std::string, DefectTally> defects;            // always bend, clearance, foreign_object; sorted by kind
  ErrorStats bend_radius_error_pct;                      // absolute errors
  std::size_t bend_radius_missing = 0;                   // truth has a radius, the report none
  ErrorStats gap_error_mm;                               // absolute errors
  GapErrors gap_error_seen;                             // ... of the gaps whose both surfaces were seen
  // ... per defect kind (clearance: read from the models; foreign_object: from its seen points)
  std::map<std::string, GapErrors> gap_error_by_kind;
  ErrorStats seconds_per_scene;                          // scenes that ran
  // Registration against the truth: within the goal (<= 0.1 deg and <= 0.3 mm at the scene's points).
  std::size_t registration_compared = 0, registration_within_goal = 0;
  ErrorStats registration_rotation_deg, registration_error_mm;
};
EvaluationSummary summarize(const std::vector<SceneEvaluation>& scenes);

// evaluation.json (evaluation.schema.json plus extra fields), fixed number format. Times are the only
// numbers that change between runs.
std::string evaluation_to_json(const EvaluationSummary& summary, const std::vector<SceneEvaluation>& scenes);
// evaluation.md: summary, defects per kind, per-scene table (verdict, expected, outcome, time), failed runs.
std::string evaluation_to_markdown(const EvaluationSummary& summary, const std::vector<SceneEvaluation>& scenes,
                                   const std::string& campaign_dir);

// The scene sub-folders of campaign_dir holding scene.obj, plan.json, scan.ply, truth.json and (with `need_pose`)
// pose.txt, sorted by name. Throws InputError when campaign_dir is not a readable folder.
std::vector<std::string> campaign_scenes(const std::string& campaign_dir, bool need_pose = true);

struct EvaluateParams {
  RunInspectionParams run;
  bool use_pose = true;                 // false: pose.txt is ignored and every scene is registered globally
  // Called after each scene (for progress lines on stderr): index, count, the scene's evaluation.
  std::function<void(std::size_t, std::size_t, const SceneEvaluation&)> on_scene;
  ProgressFn progress;                  // inside one inspection
};

struct CampaignEvaluation {
  std::vector<SceneEvaluation> scenes;
  EvaluationSummary summary;
};

// Runs the inspection of every scene into out_dir/<scene>/, compares, writes out_dir/evaluation.json and
// out_dir/evaluation.md. A scene whose inspection throws is a failed run; the evaluation goes on. Throws
// InputError when campaign_dir holds no scene or out_dir cannot be written.
CampaignEvaluation evaluate_campaign(const std::string& campaign_dir, const std::string& out_dir,
                                     const EvaluateParams& params = {});

}  // namespace ewis
