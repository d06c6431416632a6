// One scene: report.json against truth.json (rules in include/ewis/report/evaluation.hpp).
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "ewis/core/error.hpp"
#include "ewis/report/evaluation.hpp"

namespace ewis {

namespace {

using nlohmann::json;

json parse(const std::string& text, const std::string& path) {
  try {
    json j = json::parse(text);
    if (!j.is_object()) throw InputError(path, "not a JSON object");
    return j;
  } catch (const json::exception& e) {
    throw InputError(path, std::string("malformed JSON: ") + e.what());
  }
}

std::optional<double> opt_number(const json& obj, const char* key) {
  if (!obj.is_object()) return std::nullopt;
  const auto it = obj.find(key);
  if (it == obj.end() || !it->is_number()) return std::nullopt;
  const double v = it->get<double>();
  return std::isfinite(v) ? std::optional<double>(v) : std::nullopt;
}

std::optional<std::string> opt_string(const json& obj, const char* key) {
  const auto it = obj.find(key);
  if (it == obj.end() || !it->is_string()) return std::nullopt;
  return it->get<std::string>();
}

// The report's cable entry of that name, or nullptr.
const json* report_cable(const json& elements, const std::string& name) {
  for (const json& e : elements)
    if (e.is_object() && e.value("name", std::string()) == name && e.value("kind", std::string("cable")) == "cable")
      return &e;
  return nullptr;
}

bool is_false(const json& e, const char* key) {
  const auto it = e.find(key);
  return it != e.end() && it->is_boolean() && !it->get<bool>();
}

// A JSON array of 3 numbers as a point, else nullopt.
std::optional<Eigen::Vector3d> as_point(const json& q) {
  if (!q.is_array() || q.size() != 3 || !q[0].is_number() || !q[1].is_number() || !q[2].is_number())
    return std::nullopt;
  return Eigen::Vector3d(q[0].get<double>(), q[1].get<double>(), q[2].get<double>());
}

// The point under `key`, else nullopt.
std::optional<Eigen::Vector3d> opt_point(const json& obj, const char* key) {
  const auto it = obj.find(key);
  return it == obj.end() ? std::nullopt : as_point(*it);
}

// A foreign object is found only by an entry near it: its closest point on the object or its centre within this of
// the truth defect's `location` (the gap's spot on the cable), when the truth gives one. A clump of noise elsewhere
// along the same cable is a false report, not the object found (the campaigns' objects are up to 40 mm long).
constexpr double kForeignMatchMm = 30.0;

// The smallest min_distance_mm among the interferences of `cable` whose `with` matches (nullopt: null) and, with
// `near` given, whose closest_on_other or center lies within kForeignMatchMm of it. False when there is none.
bool match_interference(const json* cable, const std::optional<std::string>& with, double& gap_mm,
                        const std::optional<Eigen::Vector3d>& near = std::nullopt) {
  if (!cable) return false;
  const auto it = cable->find("interferences");
  if (it == cable->end() || !it->is_array()) return false;
  bool any = false;
  for (const json& f : *it) {
    if (!f.is_object()) continue;
    const auto w = f.find("with");
    const bool f_null = w == f.end() || w->is_null();
    const bool same = with ? (!f_null && w->is_string() && w->get<std::string>() == *with) : f_null;
    if (!same) continue;
    if (near) {
      const auto a = opt_point(f, "closest_on_other"), b = opt_point(f, "center");
      if (!(a && (*a - *near).norm() <= kForeignMatchMm) && !(b && (*b - *near).norm() <= kForeignMatchMm)) continue;
    }
    const double d = opt_number(f, "min_distance_mm").value_or(0.0);
    if (!any || d < gap_mm) gap_mm = d;
    any = true;
  }
  return any;
}

// A 4x4 row-major matrix as a JSON array of 4 arrays of 4 numbers; false when it is not one.
bool read_matrix(const json& j, Eigen::Matrix4d& m) {
  if (!j.is_array() || j.size() != 4) return false;
  for (int r = 0; r < 4; ++r) {
    if (!j[r].is_array() || j[r].size() != 4) return false;
    for (int c = 0; c < 4; ++c) {
      if (!j[r][c].is_number()) return false;
      m(r, c) = j[r][c].get<double>();
    }
  }
  return m.allFinite();
}

}  // namespace

const char* verdict_outcome_name(VerdictOutcome o) {
  switch (o) {
    case VerdictOutcome::Correct: return "correct";
    case VerdictOutcome::FalseAlarm: return "false alarm";
    case VerdictOutcome::Missed: return "missed";
    default: return "not run";
  }
}

SceneEvaluation compare_with_truth(const std::string& report_json, const std::string& truth_json,
                                   const std::string& scene_name, const std::string& report_path,
                                   const std::string& truth_path) {
  const json report = parse(report_json, report_path);
  const json truth = parse(truth_json, truth_path);
  const auto verdict = report.find("verdict");
  if (verdict == report.end() || !verdict->is_string() ||
      (verdict->get<std::string>() != "pass" && verdict->get<std::string>() != "fail"))
    throw InputError(report_path, "no \"verdict\" of pass or fail");
  const auto elements = report.find("elements");
  if (elements == report.end() || !elements->is_array()) throw InputError(report_path, "no \"elements\" array");
  const auto defects = truth.find("defects");
  if (defects == truth.end() || !defects->is_array()) throw InputError(truth_path, "no \"defects\" array");
  const auto cables = truth.find("cables");
  if (cables == truth.end() || !cables->is_array()) throw InputError(truth_path, "no \"cables\" array");

  SceneEvaluation s;
  s.scene = scene_name;
  s.ran = true;
  s.verdict = verdict->get<std::string>();
  s.truth_has_defects = !defects->empty();
  const bool fail = s.verdict == "fail";
  s.outcome = fail == s.truth_has_defects ? VerdictOutcome::Correct
                                          : (fail ? VerdictOutcome::FalseAlarm : VerdictOutcome::Missed);

  for (const json& d : *defects) {
    if (!d.is_object()) throw InputError(truth_path, "a defect is not an object");
    DefectCheck c;
    const auto kind = opt_string(d, "kind");
    const auto element = opt_string(d, "element");
    if (!kind || !element) throw InputError(truth_path, "a defect lacks \"kind\" or \"element\"");
    c.kind = *kind;
    c.element = *element;
    c.with = opt_string(d, "with");
    const json* cable = report_cable(*elements, c.element);
    if (c.kind == "bend") {
      c.truth_radius_mm = opt_number(d, "radius_mm");
      c.found = cable && is_false(*cable, "bend_ok");
    } else if (c.kind == "clearance" || c.kind == "foreign_object") {
      c.truth_gap_mm = opt_number(d, "gap_mm");
      if (const auto seen = d.find("seen"); seen != d.end() && seen->is_boolean()) c.truth_gap_seen = seen->get<bool>();
      if (c.kind == "foreign_object") c.with.reset();  // foreign: `with` null by definition
      double gap = 0.0;
      c.found = c.kind == "foreign_object" ? match_interference(cable, c.with, gap, opt_point(d, "location"))
                                           : match_interference(cable, c.with, gap);
      // Cable to cable: one gap, which the report may list on either cable.
      if (!c.found && c.with) {
        const json* other = report_cable(*elements, *c.with);
        c.found = match_interference(other, c.element, gap);
      }
      if (c.found) c.measured_gap_mm = gap;
    } else {
      c.found = !cable || is_false(*cable, "found") || is_false(*cable, "bend_ok") || is_false(*cable, "clearance_ok");
    }
    s.defects.push_back(std::move(c));
  }

  for (const json& t : *cables) {
    if (!t.is_object()) throw InputError(truth_path, "a cable is not an object");
    const auto radius = opt_number(t, "min_bend_radius_mm");
    const auto name = opt_string(t, "name");
    if (!radius || !name || *radius <= 0) continue;  // straight in truth: nothing to compare
    BendCheck b;
    b.cable = *name;
    b.truth_mm = *radius;
    b.truth_diameter_mm = opt_number(t, "diameter_mm").value_or(0.0);
    if (const json* cable = report_cable(*elements, b.cable)) {
      b.measured_mm = opt_number(*cable, "min_bend_radius_mm");
      b.measured_se_mm = opt_number(*cable, "min_bend_radius_se_mm");
      const auto bound = cable->find("min_bend_radius_is_bound");
      b.measured_is_bound = bound != cable->end() && bound->is_boolean() && bound->get<bool>();
    }
    if (b.measured_mm) b.error_pct = (*b.measured_mm - b.truth_mm) / b.truth_mm * 100.0;
    s.bends.push_back(std::move(b));
  }

  // Registration: the difference of the two scan-to-CAD transforms, measured at the truth's cable points.
  Eigen::Matrix4d measured, truth_pose;
  const auto reg = report.find("registration");
  const auto cam = truth.find("camera_to_cad");
  if (reg != report.end() && reg->is_object() && reg->contains("transform") && cam != truth.end() &&
      read_matrix((*reg)["transform"], measured) && read_matrix(*cam, truth_pose)) {
    const Eigen::Matrix4d diff = measured * truth_pose.inverse();
    const double c = std::clamp((diff.topLeftCorner<3, 3>().trace() - 1.0) / 2.0, -1.0, 1.0);
    s.registration_rotation_deg = std::acos(c) * 180.0 / M_PI;
    double worst = 0.0;
    bool any = false;
    for (const json& t : *cables) {
      const auto cl = t.find("centerline");
      if (cl == t.end() || !cl->is_array()) continue;
      for (const json& q : *cl) {
        const std::optional<Eigen::Vector3d> point = as_point(q);
        if (!point) continue;
        const Eigen::Vector4d p = point->homogeneous();
        worst = std::max(worst, (diff * p - p).head<3>().norm());
        any = true;
      }
    }
    if (any) s.registration_error_mm = worst;
  }
  return s;
}

}  // namespace ewis
