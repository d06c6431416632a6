// The inspection plan of CONTRACT.md ("Inspection plan"), checked as shared/schemas/plan.schema.json says, plus
// the rules a schema cannot say (unique names, exactly one bend rule, no element attached to itself).
#include <cmath>
#include <nlohmann/json.hpp>
#include <set>

#include "ewis/core/error.hpp"
#include "ewis/io/plan_file.hpp"
#include "file_bytes.hpp"

namespace ewis {

namespace {

using json = nlohmann::json;

struct Checker {
  const std::string& path;
  [[noreturn]] void fail(const std::string& what) const { throw InputError(path, what); }

  double number(const json& obj, const char* key, const std::string& where) const {
    const json& v = obj.at(key);
    if (!v.is_number()) fail(where + ": '" + key + "' must be a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) fail(where + ": '" + key + "' must be finite");
    return d;
  }
  double positive(const json& obj, const char* key, const std::string& where) const {
    const double d = number(obj, key, where);
    if (!(d > 0)) fail(where + ": '" + key + "' must be > 0 (got " + obj.at(key).dump() + ")");
    return d;
  }
  int positive_int(const json& obj, const char* key, const std::string& where) const {
    const json& v = obj.at(key);
    if (!v.is_number_integer() && !(v.is_number_float() && v.get<double>() == std::floor(v.get<double>())))
      fail(where + ": '" + key + "' must be an integer");
    const double d = v.get<double>();
    if (!(d >= 1) || d > 1e6) fail(where + ": '" + key + "' must be between 1 and 1000000");
    return static_cast<int>(d);
  }
  std::string string(const json& obj, const char* key, const std::string& where) const {
    const json& v = obj.at(key);
    if (!v.is_string()) fail(where + ": '" + key + "' must be a string");
    return v.get<std::string>();
  }
};

SensorModel parse_sensor(const Checker& ck, const json& s) {
  SensorModel m;
  const std::string where = "sensor";
  if (!s.is_object()) ck.fail("'sensor' must be an object");
  if (s.contains("width_px")) m.width_px = ck.positive_int(s, "width_px", where);
  if (s.contains("height_px")) m.height_px = ck.positive_int(s, "height_px", where);
  if (s.contains("hfov_deg")) {
    m.hfov_deg = ck.positive(s, "hfov_deg", where);
    if (m.hfov_deg >= 180) ck.fail("sensor: 'hfov_deg' must be below 180");
  }
  if (s.contains("standoff_mm")) m.standoff_mm = ck.positive(s, "standoff_mm", where);
  return m;
}

PlanElement parse_element(const Checker& ck, const json& e, std::size_t index) {
  std::string where = "elements[" + std::to_string(index) + "]";
  if (!e.is_object()) ck.fail(where + " must be an object");
  if (!e.contains("name")) ck.fail(where + ": missing 'name'");
  PlanElement el;
  el.name = ck.string(e, "name", where);
  if (el.name.empty()) ck.fail(where + ": 'name' must not be empty");
  where = "element '" + el.name + "'";
  if (!e.contains("kind")) ck.fail(where + ": missing 'kind' (cable or rigid)");
  const std::string kind = ck.string(e, "kind", where);
  if (kind == "cable") el.kind = ElementKind::Cable;
  else if (kind == "rigid") el.kind = ElementKind::Rigid;
  else ck.fail(where + ": unknown kind '" + kind + "' (expected cable or rigid)");

  if (e.contains("diameter_mm")) el.diameter_mm = ck.positive(e, "diameter_mm", where);
  if (e.contains("min_bend_radius_mm")) el.min_bend_radius_mm = ck.positive(e, "min_bend_radius_mm", where);
  if (e.contains("min_bend_ratio")) el.min_bend_ratio = ck.positive(e, "min_bend_ratio", where);
  if (e.contains("clearance_mm")) {
    el.clearance_mm = ck.number(e, "clearance_mm", where);
    if (el.clearance_mm < 0) ck.fail(where + ": 'clearance_mm' must be >= 0");
  }
  if (e.contains("bend_radius_reference")) {
    const std::string ref = ck.string(e, "bend_radius_reference", where);
    if (ref == "centreline" || ref == "centerline") el.bend_reference = BendReference::Centreline;
    else if (ref == "inner") el.bend_reference = BendReference::Inner;
    else ck.fail(where + ": 'bend_radius_reference' must be \"centreline\" or \"inner\" (got \"" + ref + "\")");
  }
  if (e.contains("attached")) {
    const json& a = e.at("attached");
    if (!a.is_array()) ck.fail(where + ": 'attached' must be a list of element names");
    for (const json& n : a) {
      if (!n.is_string() || n.get<std::string>().empty())
        ck.fail(where + ": 'attached' must be a list of element names");
      if (n.get<std::string>() == el.name) ck.fail(where + ": attached to itself");
      el.attached.push_back(n.get<std::string>());
    }
  }
  if (el.kind == ElementKind::Cable) {
    if (!e.contains("diameter_mm")) ck.fail(where + ": a cable needs 'diameter_mm' (> 0)");
    // CONTRACT.md: min_bend_radius_mm "may be replaced by" min_bend_ratio: one rule, not both, not none.
    if (el.min_bend_radius_mm && el.min_bend_ratio)
      ck.fail(where + ": give either 'min_bend_radius_mm' or 'min_bend_ratio', not both");
    if (!el.min_bend_radius_mm && !el.min_bend_ratio)
      ck.fail(where + ": a cable needs 'min_bend_radius_mm' or 'min_bend_ratio'");
  }
  return el;
}

}  // namespace

InspectionPlan parse_plan(const std::string& json_text, const std::string& path) {
  const Checker ck{path};
  json doc;
  try {
    doc = json::parse(json_text);
  } catch (const json::exception& e) {  // parse errors, and number overflow (out_of_range 406)
    // nlohmann's message says where ("at line 3, column 7") and what.
    std::string what = e.what();
    const auto p = what.find("parse error");
    ck.fail("invalid JSON: " + (p == std::string::npos ? what : what.substr(p)));
  }
  if (!doc.is_object()) ck.fail("the plan must be a JSON object");
  InspectionPlan plan;
  if (doc.contains("units")) {
    if (!doc["units"].is_string() || doc["units"].get<std::string>() != "mm")
      ck.fail("'units' must be \"mm\" (got " + doc["units"].dump() + ")");
  }
  if (doc.contains("sensor")) plan.sensor = parse_sensor(ck, doc["sensor"]);
  if (!doc.contains("elements")) ck.fail("missing 'elements'");
  const json& els = doc["elements"];
  if (!els.is_array()) ck.fail("'elements' must be a list");
  std::set<std::string> names;
  for (std::size_t i = 0; i < els.size(); ++i) {
    PlanElement el = parse_element(ck, els[i], i);
    if (!names.insert(el.name).second) ck.fail("element '" + el.name + "' is listed twice");
    plan.elements.push_back(std::move(el));
  }
  return plan;
}

InspectionPlan read_plan(const std::string& path) {
  const io_detail::FileBytes f = io_detail::read_file_bytes(path);
  return parse_plan(std::string(f.view()), path);
}

std::string plan_to_json(const InspectionPlan& plan) {
  nlohmann::ordered_json doc;
  doc["units"] = "mm";
  doc["sensor"] = {{"width_px", plan.sensor.width_px},
                   {"height_px", plan.sensor.height_px},
                   {"hfov_deg", plan.sensor.hfov_deg},
                   {"standoff_mm", plan.sensor.standoff_mm}};
  doc["elements"] = nlohmann::ordered_json::array();
  for (const auto& e : plan.elements) {
    nlohmann::ordered_json j;
    j["name"] = e.name;
    j["kind"] = e.kind == ElementKind::Cable ? "cable" : "rigid";
    if (e.kind == ElementKind::Cable || e.diameter_mm > 0) j["diameter_mm"] = e.diameter_mm;
    if (e.min_bend_radius_mm) j["min_bend_radius_mm"] = *e.min_bend_radius_mm;
    if (e.min_bend_ratio) j["min_bend_ratio"] = *e.min_bend_ratio;
    if (e.kind == ElementKind::Cable || e.clearance_mm != 0) j["clearance_mm"] = e.clearance_mm;
    if (e.kind == ElementKind::Cable || e.bend_reference != BendReference::Centreline)
      j["bend_radius_reference"] = e.bend_reference == BendReference::Inner ? "inner" : "centreline";
    if (!e.attached.empty()) j["attached"] = e.attached;
    doc["elements"].push_back(std::move(j));
  }
  return doc.dump(2) + "\n";
}

}  // namespace ewis
