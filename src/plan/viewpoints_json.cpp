// viewpoints.json (CONTRACT.md "ewis plan"), with the extra fields docs/plan.md describes.
#include <cmath>
#include <nlohmann/json.hpp>

#include "ewis/plan/viewpoint_plan.hpp"

namespace ewis {
namespace {

using json = nlohmann::ordered_json;  // keeps the contract's field order

// Rounded to `decimals` so that float noise (1e-14 for 0, -0) does not reach the file; 1e-9 mm is far below
// any use. Dividing the rounded integer by the power of ten gives the double nearest the decimal, which
// prints short.
double clean(double x, int decimals = 9) {
  const double scale = std::pow(10.0, decimals);
  const double r = std::round(x * scale) / scale;
  return r == 0.0 || !std::isfinite(r) ? 0.0 : r;
}

json vec3(const Eigen::Vector3d& v) { return json::array({clean(v.x()), clean(v.y()), clean(v.z())}); }

json matrix(const Pose& pose) {
  const Eigen::Matrix4d m = pose.matrix();
  json rows = json::array();
  for (int r = 0; r < 4; ++r) {
    json row = json::array();
    for (int c = 0; c < 4; ++c) row.push_back(clean(m(r, c)));
    rows.push_back(row);
  }
  return rows;
}

json entry(const ElementViewpoints& ev, std::size_t candidate, std::size_t rank, bool name_it) {
  const Candidate& c = ev.grid.candidates[candidate];
  const CandidateScore& s = ev.scores[candidate];
  json j;
  j["rank"] = rank;
  if (name_it) j["element"] = ev.name;
  j["position"] = vec3(c.position);
  j["target"] = vec3(c.target);
  j["camera_to_cad"] = matrix(c.camera_to_cad);
  j["score_px"] = s.score_px;
  j["visible_fraction"] = clean(s.visible_fraction);
  j["theta_deg"] = clean(c.theta_deg);
  j["phi_deg"] = clean(c.phi_deg);
  j["candidate_index"] = candidate;
  if (s.rejected) j["rejected"] = s.reject_reason;
  return j;
}

std::size_t rejected_count(const ElementViewpoints& ev) {
  std::size_t n = 0;
  for (const auto& s : ev.scores) n += s.rejected ? 1 : 0;
  return n;
}

}  // namespace

std::string viewpoints_json(const ViewpointPlan& plan) {
  const bool multi = plan.elements.size() > 1;
  json out;
  std::string names;
  std::size_t candidates = 0, rejected = 0;
  for (const auto& ev : plan.elements) {
    names += (names.empty() ? "" : ",") + ev.name;
    candidates += ev.grid.candidates.size();
    rejected += rejected_count(ev);
  }
  out["element"] = names;
  out["candidates"] = candidates;
  json best = json::array();
  for (std::size_t i = 0; i < plan.best.size(); ++i) {
    json j = entry(plan.elements[plan.best[i].first], plan.best[i].second, i + 1, multi);
    j["image"] = "view_" + std::to_string(i + 1) + ".png";
    best.push_back(j);
  }
  out["best"] = best;
  const CandidateParams& cp = plan.params.candidates;
  out["radius_mm"] = clean(cp.radius_mm);
  out["step_deg"] = clean(cp.step_deg);
  out["theta_range_deg"] = json::array({clean(cp.theta_min_deg), clean(cp.theta_max_deg)});
  out["phi_range_deg"] = json::array({clean(cp.phi_min_deg), clean(cp.phi_max_deg)});
  out["score"] = plan.params.score.measurable ? "measurable_pixels" : "visible_pixels";
  out["sensor"] = {{"width_px", plan.sensor.width_px}, {"height_px", plan.sensor.height_px},
                   {"hfov_deg", clean(plan.sensor.hfov_deg)}, {"standoff_mm", clean(plan.sensor.standoff_mm)},
                   {"focal_px", clean(plan.sensor.camera().focal_px(), 6)}};
  out["rejected"] = rejected;
  out["heatmap"] = "heatmap.png";
  if (multi) {
    json elements = json::array();
    for (const auto& ev : plan.elements) {
      json e;
      e["name"] = ev.name;
      e["center"] = vec3(ev.grid.candidates.empty() ? Eigen::Vector3d::Zero() : ev.grid.candidates.front().target);
      e["candidates"] = ev.grid.candidates.size();
      e["rejected"] = rejected_count(ev);
      json eb = json::array();
      for (std::size_t i = 0; i < ev.best.size(); ++i) eb.push_back(entry(ev, ev.best[i], i + 1, false));
      e["best"] = eb;
      elements.push_back(e);
    }
    out["elements"] = elements;
  }
  if (plan.has_coverage) {
    const CoverageSet& cs = plan.coverage;
    json c;
    c["target_fraction"] = clean(cs.target_fraction);
    c["complete"] = cs.complete;
    c["size"] = cs.viewpoints.size();
    c["optimal_size_at_least"] = cs.lower_bound;
    c["greedy_bound_factor"] = clean(cs.greedy_factor, 6);
    c["samples_per_element"] = cs.samples_per_element;
    json cov = json::array();
    for (std::size_t k = 0; k < plan.elements.size(); ++k)
      cov.push_back({{"name", plan.elements[k].name},
                     {"coverage", clean(k < cs.coverage.size() ? cs.coverage[k] : 0.0, 6)},
                     {"best_single_view", clean(k < cs.best_single.size() ? cs.best_single[k] : 0.0, 6)},
                     {"reachable", clean(k < cs.reachable.size() ? cs.reachable[k] : 0.0, 6)}});
    c["elements"] = cov;
    json views = json::array();
    for (std::size_t i = 0; i < cs.viewpoints.size(); ++i) {
      const CoverageViewpoint& v = cs.viewpoints[i];
      json j = entry(plan.elements[v.sphere], v.candidate, i + 1, false);
      j.erase("rank");
      json head;
      head["order"] = i + 1;
      head["sphere_of"] = plan.elements[v.sphere].name;
      for (auto it = j.begin(); it != j.end(); ++it) head[it.key()] = it.value();
      json gained = json::object();
      for (std::size_t k = 0; k < v.gained.size() && k < plan.elements.size(); ++k)
        gained[plan.elements[k].name] = clean(v.gained[k], 6);
      head["adds_coverage"] = gained;
      head["image"] = "cover_" + std::to_string(i + 1) + ".png";
      views.push_back(head);
    }
    c["viewpoints"] = views;
    out["coverage_set"] = c;
  }
  return out.dump(2) + "\n";
}

}  // namespace ewis
