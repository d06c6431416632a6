// Paper 3.1: candidates on a sphere around the element's centre of mass, each scored, the best selected.
#include "ewis/plan/viewpoint_plan.hpp"

#include <algorithm>
#include <numeric>

#include "ewis/core/error.hpp"
#include "ewis/raycast/raycaster.hpp"

namespace ewis {
namespace {

// score_px descending; ties keep candidate order (stable sort of the index order).
std::vector<std::size_t> rank_candidates(const std::vector<CandidateScore>& scores, std::size_t top) {
  std::vector<std::size_t> order(scores.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return scores[a].score_px > scores[b].score_px; });
  order.resize(std::min(top, order.size()));
  return order;
}

}  // namespace

std::vector<std::uint32_t> resolve_elements(const Scene& scene, const InspectionPlan& plan,
                                            const std::vector<std::string>& names, const std::string& cad_path,
                                            const std::string& plan_path) {
  std::vector<std::uint32_t> out;
  auto add = [&](std::uint32_t e) {
    if (std::find(out.begin(), out.end(), e) == out.end()) out.push_back(e);
  };
  if (names.empty()) throw InputError("", "no --element given");
  // The plan must describe this CAD: an element it names that the CAD lacks is a contradiction (as in inspect).
  for (const PlanElement& pe : plan.elements)
    if (scene.find(pe.name) < 0)
      throw InputError(plan_path, "element '" + pe.name + "' of the plan is not an object of the CAD " + cad_path);
  for (const std::string& name : names) {
    if (name == "all-cables") {
      std::size_t cables = 0;
      for (const PlanElement& pe : plan.elements) {
        if (pe.kind != ElementKind::Cable) continue;
        ++cables;
        const int e = scene.find(pe.name);
        if (e < 0) throw InputError(cad_path, "cable '" + pe.name + "' of the plan is not an element of the CAD scene");
        add(static_cast<std::uint32_t>(e));
      }
      if (cables == 0) throw InputError(plan_path, "'all-cables' given but the plan lists no cable");
      continue;
    }
    const int e = scene.find(name);
    if (e < 0) throw InputError(cad_path, "unknown element '" + name + "' (not an object of the CAD scene)");
    add(static_cast<std::uint32_t>(e));
  }
  for (std::uint32_t e : out)
    if (scene.elements[e].triangle_count == 0)
      throw InputError(cad_path, "element '" + scene.elements[e].name + "' has no triangles");
  return out;
}

ViewpointPlan plan_viewpoints(const Scene& scene, const SensorModel& sensor,
                              const std::vector<std::uint32_t>& elements, const ViewpointParams& params,
                              const ProgressFn& progress) {
  ViewpointPlan plan;
  plan.sensor = sensor;
  plan.params = params;
  if (!(plan.params.candidates.radius_mm > 0)) plan.params.candidates.radius_mm = sensor.standoff_mm;
  if (plan.params.top == 0) plan.params.top = 1;
  const Camera camera = sensor.camera();
  const Raycaster scene_caster(scene);
  for (std::uint32_t e : elements) {
    if (e >= scene.elements.size()) throw InputError("", "element index out of range");
    ElementViewpoints ev;
    ev.name = scene.elements[e].name;
    ev.element = e;
    ev.grid = make_candidates(scene.elements[e].center_of_mass, plan.params.candidates);
    ev.scores = score_candidates(scene_caster, camera, e, ev.grid.candidates, plan.params.candidates.radius_mm,
                                 plan.params.score, progress);
    ev.best = rank_candidates(ev.scores, plan.params.top);
    plan.elements.push_back(std::move(ev));
  }
  // visible_fraction costs a second render: only for the views reported (the best lists; coverage below).
  auto fractions = [&](ElementViewpoints& ev, const std::vector<std::size_t>& which) {
    std::vector<bool> only(scene.elements.size(), false);
    only[ev.element] = true;
    const Raycaster element_caster(scene, only);
    add_visible_fractions(element_caster, camera, ev.element, ev.grid.candidates, plan.params.score, ev.scores, which);
  };
  for (ElementViewpoints& ev : plan.elements)
    if (!ev.best.empty()) fractions(ev, ev.best);
  // The top-level list: the best views over every sphere (one element: that element's list).
  std::vector<std::pair<std::size_t, std::size_t>> all;
  for (std::size_t s = 0; s < plan.elements.size(); ++s)
    for (std::size_t c : plan.elements[s].best) all.emplace_back(s, c);
  std::stable_sort(all.begin(), all.end(), [&](const auto& a, const auto& b) {
    return plan.elements[a.first].scores[a.second].score_px > plan.elements[b.first].scores[b.second].score_px;
  });
  all.resize(std::min(all.size(), plan.params.top));
  plan.best = std::move(all);

  if (plan.elements.size() > 1 || plan.params.force_coverage) {
    // Issue 7, 4b: every candidate of every sphere may serve any element.
    std::vector<Pose> views;
    std::vector<bool> usable;
    std::vector<std::pair<std::size_t, std::size_t>> origin;
    for (std::size_t s = 0; s < plan.elements.size(); ++s)
      for (std::size_t c = 0; c < plan.elements[s].grid.candidates.size(); ++c) {
        views.push_back(plan.elements[s].grid.candidates[c].camera_to_cad);
        usable.push_back(!plan.elements[s].scores[c].rejected);
        origin.emplace_back(s, c);
      }
    CoverageParams cp = plan.params.coverage;
    if (plan.params.score.measurable) cp.measurable = true, cp.sensor = plan.params.score.sensor;
    const SurfaceSamples samples = sample_elements(scene, elements, cp.samples_per_element, cp.seed);
    const VisibilitySets sets = visible_samples(scene_caster, camera, views, usable, samples, cp, progress);
    const CoverResult cover = greedy_cover(sets, cp.target_fraction, cp.max_viewpoints, cp.min_gain_fraction);
    plan.has_coverage = true;
    plan.coverage.target_fraction = cp.target_fraction;
    plan.coverage.samples_per_element = cp.samples_per_element;
    for (std::size_t i = 0; i < cover.chosen.size(); ++i) {
      CoverageViewpoint v;
      v.sphere = origin[cover.chosen[i]].first;
      v.candidate = origin[cover.chosen[i]].second;
      v.gained = cover.gained[i];
      plan.coverage.viewpoints.push_back(std::move(v));
    }
    plan.coverage.coverage = cover.coverage;
    plan.coverage.best_single = cover.best_single;
    plan.coverage.reachable = cover.reachable;
    plan.coverage.complete = cover.complete;
    plan.coverage.lower_bound = cover.lower_bound;
    plan.coverage.greedy_factor = cover.greedy_factor;
    for (std::size_t s = 0; s < plan.elements.size(); ++s) {
      std::vector<std::size_t> which;
      for (const CoverageViewpoint& v : plan.coverage.viewpoints)
        if (v.sphere == s && plan.elements[s].scores[v.candidate].isolated_px == 0) which.push_back(v.candidate);
      if (!which.empty()) fractions(plan.elements[s], which);
    }
  }
  return plan;
}

}  // namespace ewis
