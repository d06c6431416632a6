// ewis evaluate: the paper's campaign experiment (CONTRACT.md "ewis evaluate"): inspects every scene of a
// simulated campaign in-process, compares each report with truth.json, writes DIR2/<scene>/ outputs,
// DIR2/evaluation.json and DIR2/evaluation.md. Progress (one line per scene) on stderr.
#include <cstdio>
#include <iostream>

#include "common.hpp"
#include "ewis/report/evaluation.hpp"

namespace ewis::cli {

Command add_evaluate(CLI::App& root, CommonOptions& common) {
  struct Options {
    std::string campaign, out;
    bool no_html = false;
    bool no_clouds = false;
    bool no_pose = false;
  };
  auto opt = std::make_shared<Options>();
  Command cmd;
  cmd.app = root.add_subcommand("evaluate",
                                "Inspect every scene of a simulated campaign and compare with its truth.json "
                                "(detection rates, false alarms, bend-radius and gap errors, time per scene)");
  cmd.app->add_option("--campaign", opt->campaign, "Campaign folder written by `ewis simulate --campaign N`")->required();
  cmd.app->add_option("--out", opt->out, "Output folder: <scene>/ reports, evaluation.json, evaluation.md")->required();
  cmd.app->add_flag("--no-html", opt->no_html, "Skip report.html of each scene (faster)");
  cmd.app->add_flag("--no-clouds", opt->no_clouds,
                    "Skip the coloured PLY files of each scene (cables, interferences, rest: ~12 MB a scene)");
  cmd.app->add_flag("--no-pose", opt->no_pose,
                    "Ignore each scene's pose.txt (which may then be absent): register globally (measures "
                    "registration without a pose)");
  add_common_options(cmd.app, common);
  cmd.run = [opt, &common]() -> int {
    EvaluateParams params;
    params.run.write_html = !opt->no_html;
    params.run.write_clouds = !opt->no_clouds;
    params.use_pose = !opt->no_pose;
    params.progress = make_progress(common);  // steps inside each inspection (scenes take seconds to minutes)
    params.on_scene = [&common](std::size_t i, std::size_t n, const SceneEvaluation& e) {
      if (common.quiet) return;
      char line[512];
      if (e.ran) {
        std::size_t found = 0;
        for (const DefectCheck& d : e.defects) found += d.found;
        std::snprintf(line, sizeof line, "scene %zu/%zu %s: %s, expected %s (%s), defects found %zu/%zu, %.2f s", i + 1,
                      n, e.scene.c_str(), e.verdict.c_str(), e.truth_has_defects ? "fail" : "pass",
                      verdict_outcome_name(e.outcome), found, e.defects.size(), e.seconds);
      } else {
        std::snprintf(line, sizeof line, "scene %zu/%zu %s: FAILED RUN: %s", i + 1, n, e.scene.c_str(), e.error.c_str());
      }
      log(common, line);
    };
    const CampaignEvaluation ev = evaluate_campaign(opt->campaign, opt->out, params);
    const EvaluationSummary& s = ev.summary;
    char line[512];
    std::snprintf(line, sizeof line,
                  "evaluated %zu scenes: %zu correct, %zu false alarms, %zu missed, %zu failed runs; see %s/evaluation.md",
                  s.scenes, s.correct, s.false_alarms, s.missed, s.failed_runs, opt->out.c_str());
    log(common, line);
    return 0;
  };
  return cmd;
}

}  // namespace ewis::cli
