// The files of `ewis plan`: pictures first, viewpoints.json last, each written atomically.
#include <filesystem>

#include "ewis/io/cloud_io.hpp"
#include "ewis/io/image_io.hpp"
#include "ewis/plan/images.hpp"
#include "ewis/plan/viewpoint_plan.hpp"

namespace ewis {
namespace {

std::string safe_name(const std::string& name) {
  std::string s;
  for (char ch : name) s += (std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '_') ? ch : '_';
  return s.empty() ? "element" : s;
}

}  // namespace

void write_viewpoint_outputs(const Scene& scene, const ViewpointPlan& plan, const std::string& dir,
                             const ProgressFn& progress) {
  const std::filesystem::path folder(dir);
  const Camera camera = plan.sensor.camera();
  const Raycaster caster(scene);
  std::vector<std::uint32_t> listed;
  for (const auto& ev : plan.elements) listed.push_back(ev.element);
  const std::size_t total = plan.best.size() + (plan.has_coverage ? plan.coverage.viewpoints.size() : 0);
  std::size_t done = 0;
  for (std::size_t i = 0; i < plan.best.size(); ++i) {
    const ElementViewpoints& ev = plan.elements[plan.best[i].first];
    std::vector<std::uint32_t> others;
    for (std::uint32_t e : listed)
      if (e != ev.element) others.push_back(e);
    const Image img = render_highlight(caster, camera, ev.grid.candidates[plan.best[i].second].camera_to_cad,
                                       {ev.element}, others);
    write_png(img, (folder / ("view_" + std::to_string(i + 1) + ".png")).string());
    if (progress) progress("plan: pictures", double(++done) / double(std::max<std::size_t>(total, 1)));
  }
  if (plan.has_coverage) {
    for (std::size_t i = 0; i < plan.coverage.viewpoints.size(); ++i) {
      const CoverageViewpoint& v = plan.coverage.viewpoints[i];
      const Image img =
          render_highlight(caster, camera, plan.elements[v.sphere].grid.candidates[v.candidate].camera_to_cad, listed);
      write_png(img, (folder / ("cover_" + std::to_string(i + 1) + ".png")).string());
      if (progress) progress("plan: pictures", double(++done) / double(std::max<std::size_t>(total, 1)));
    }
  }
  for (std::size_t k = 0; k < plan.elements.size(); ++k) {
    const ElementViewpoints& ev = plan.elements[k];
    const Image heat = score_heatmap(ev.grid, ev.scores, ev.best);
    if (k == 0) write_png(heat, (folder / "heatmap.png").string());
    if (plan.elements.size() > 1) write_png(heat, (folder / ("heatmap_" + safe_name(ev.name) + ".png")).string());
  }
  write_file_atomic((folder / "viewpoints.json").string(), viewpoints_json(plan));
}

}  // namespace ewis
