// `ewis evaluate`: every scene of a campaign inspected in-process, compared with its truth, summarised.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "ewis/core/error.hpp"
#include "ewis/report/evaluation.hpp"

namespace ewis {

namespace {

const char* kSceneFiles[] = {"scene.obj", "plan.json", "scan.ply", "truth.json"};

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot be read");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

std::vector<std::string> campaign_scenes(const std::string& campaign_dir, bool need_pose) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(campaign_dir, ec)) throw InputError(campaign_dir, "is not a folder");
  std::vector<std::string> names;
  fs::directory_iterator it(campaign_dir, ec), end;
  if (ec) throw InputError(campaign_dir, "cannot be read: " + ec.message());
  for (; it != end; it.increment(ec)) {
    if (ec) throw InputError(campaign_dir, "cannot be read: " + ec.message());
    if (!it->is_directory(ec)) continue;
    bool complete = true;
    for (const char* f : kSceneFiles) complete = complete && fs::is_regular_file(it->path() / f, ec);
    if (need_pose) complete = complete && fs::is_regular_file(it->path() / "pose.txt", ec);
    if (complete) names.push_back(it->path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

CampaignEvaluation evaluate_campaign(const std::string& campaign_dir, const std::string& out_dir,
                                     const EvaluateParams& params) {
  namespace fs = std::filesystem;
  const std::vector<std::string> names = campaign_scenes(campaign_dir, params.use_pose);
  if (names.empty())
    throw InputError(campaign_dir, params.use_pose
                                       ? "holds no scene folder with scene.obj, plan.json, scan.ply, pose.txt and truth.json"
                                       : "holds no scene folder with scene.obj, plan.json, scan.ply and truth.json");
  std::error_code ec;
  if (fs::exists(out_dir, ec) && !fs::is_directory(out_dir, ec)) throw InputError(out_dir, "exists and is not a directory");
  fs::create_directories(out_dir, ec);
  if (ec) throw InputError(out_dir, "cannot create directory: " + ec.message());

  CampaignEvaluation out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string dir = (fs::path(campaign_dir) / names[i]).string();
    const std::string scene_out = (fs::path(out_dir) / names[i]).string();
    InspectionInputs in;
    in.cad = dir + "/scene.obj";
    in.plan = dir + "/plan.json";
    in.scan = dir + "/scan.ply";
    if (params.use_pose) in.pose = dir + "/pose.txt";
    SceneEvaluation e;
    e.scene = names[i];
    const auto t0 = std::chrono::steady_clock::now();
    try {
      const InspectionRun run = run_inspection(in, scene_out, params.run, params.progress);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      e = compare_with_truth(run.report_json, read_text(dir + "/truth.json"), names[i], scene_out + "/report.json",
                             dir + "/truth.json");
      e.seconds = seconds;
    } catch (const std::bad_alloc&) {
      e = SceneEvaluation{};
      e.scene = names[i];
      e.error = "out of memory";
    } catch (const std::exception& ex) {
      // A scene that cannot be inspected is a failed run; the campaign goes on.
      e = SceneEvaluation{};
      e.scene = names[i];
      e.error = ex.what();
      e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    }
    out.scenes.push_back(e);
    if (params.on_scene) params.on_scene(i, names.size(), out.scenes.back());
  }
  out.summary = summarize(out.scenes);
  write_file_atomic((fs::path(out_dir) / "evaluation.json").string(), evaluation_to_json(out.summary, out.scenes));
  write_file_atomic((fs::path(out_dir) / "evaluation.md").string(),
                    evaluation_to_markdown(out.summary, out.scenes, campaign_dir));
  return out;
}

}  // namespace ewis
