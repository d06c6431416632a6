#include <gtest/gtest.h>

#include "ewis/core/error.hpp"
#include "ewis/io/plan_file.hpp"
#include "io/io_test_util.hpp"

using namespace ewis;
using namespace io_test;

namespace {

const char* kContractPlan = R"({
  "units": "mm",
  "sensor": { "width_px": 1280, "height_px": 1024, "hfov_deg": 58.0, "standoff_mm": 600.0 },
  "elements": [
    { "name": "cable_A", "kind": "cable", "diameter_mm": 10.0, "min_bend_radius_mm": 60.0, "clearance_mm": 5.0 },
    { "name": "bracket_1", "kind": "rigid" }
  ]
})";

std::string what_of(const std::string& text) {
  try {
    parse_plan(text, "plan.json");
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "plan.json");
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << text;
  return {};
}

std::string with_element(const std::string& el) { return R"({"elements": [)" + el + "]}"; }

}  // namespace

TEST(PlanFile, ContractExample) {
  const InspectionPlan p = parse_plan(kContractPlan, "plan.json");
  ASSERT_EQ(p.elements.size(), 2u);
  const PlanElement& a = p.elements[0];
  EXPECT_EQ(a.name, "cable_A");
  EXPECT_EQ(a.kind, ElementKind::Cable);
  EXPECT_EQ(a.diameter_mm, 10.0);
  EXPECT_EQ(a.allowed_bend_radius_mm(), 60.0);
  EXPECT_EQ(a.clearance_mm, 5.0);
  EXPECT_EQ(a.bend_reference, BendReference::Centreline);
  EXPECT_EQ(p.elements[1].kind, ElementKind::Rigid);
  EXPECT_EQ(p.find("bracket_1"), &p.elements[1]);
  EXPECT_EQ(p.find("nope"), nullptr);
  EXPECT_EQ(p.sensor.width_px, 1280);
}

TEST(PlanFile, DefaultsRatioInnerAndAttached) {
  const InspectionPlan p = parse_plan(
      R"({"elements": [{"name": "h", "kind": "cable", "diameter_mm": 8, "min_bend_ratio": 6,
          "bend_radius_reference": "inner", "attached": ["clamp_1", "J2"]},
          {"name": "w", "kind": "cable", "diameter_mm": 4, "min_bend_radius_mm": 20,
          "bend_radius_reference": "centerline"}], "comment": "extra fields are fine"})",
      "p");
  const SensorModel def;
  EXPECT_EQ(p.sensor.width_px, def.width_px);
  EXPECT_EQ(p.sensor.hfov_deg, 58.0);
  EXPECT_EQ(p.sensor.standoff_mm, 600.0);
  const PlanElement& h = p.elements[0];
  EXPECT_EQ(h.allowed_bend_radius_mm(), 48.0);
  EXPECT_EQ(h.bend_reference, BendReference::Inner);
  EXPECT_EQ(h.attached, (std::vector<std::string>{"clamp_1", "J2"}));
  EXPECT_EQ(h.clearance_mm, 0.0);
  EXPECT_EQ(p.elements[1].bend_reference, BendReference::Centreline);
}

TEST(PlanFile, RoundTripThroughJson) {
  const InspectionPlan a = parse_plan(
      R"({"sensor": {"width_px": 640, "height_px": 480, "hfov_deg": 45.5, "standoff_mm": 350.25},
          "elements": [{"name": "c", "kind": "cable", "diameter_mm": 7.3, "min_bend_ratio": 5.5,
          "clearance_mm": 2.5, "bend_radius_reference": "inner", "attached": ["x"]},
          {"name": "x", "kind": "rigid"}, {"name": "d", "kind": "cable", "diameter_mm": 0.1,
          "min_bend_radius_mm": 0.30000000000000004}]})",
      "p");
  const std::string text = plan_to_json(a);
  const InspectionPlan b = parse_plan(text, "p2");
  EXPECT_EQ(plan_to_json(b), text);
  ASSERT_EQ(b.elements.size(), 3u);
  EXPECT_EQ(b.sensor.width_px, 640);
  EXPECT_EQ(b.sensor.standoff_mm, 350.25);
  EXPECT_EQ(b.elements[0].min_bend_ratio, 5.5);
  EXPECT_FALSE(b.elements[0].min_bend_radius_mm.has_value());
  EXPECT_EQ(b.elements[0].bend_reference, BendReference::Inner);
  EXPECT_EQ(b.elements[2].min_bend_radius_mm, 0.30000000000000004);
  EXPECT_EQ(b.elements[1].kind, ElementKind::Rigid);
}

TEST(PlanFile, ErrorsNameTheElementAndField) {
  const auto has = [](const std::string& what, const std::string& part) {
    EXPECT_NE(what.find(part), std::string::npos) << what << " lacks " << part;
  };
  has(what_of("{"), "invalid JSON");
  has(what_of("[1,2]"), "object");
  has(what_of("{}"), "elements");
  has(what_of(R"({"units": "m", "elements": []})"), "units");
  has(what_of(R"({"elements": {}})"), "elements");
  has(what_of(with_element(R"({"kind": "rigid"})")), "name");
  has(what_of(with_element(R"({"name": "", "kind": "rigid"})")), "name");
  has(what_of(with_element(R"({"name": "a"})")), "kind");
  has(what_of(with_element(R"({"name": "a", "kind": "hose"})")), "unknown kind");
  has(what_of(with_element(R"({"name": "a", "kind": "cable", "min_bend_radius_mm": 5})")), "diameter_mm");
  has(what_of(with_element(R"({"name": "a", "kind": "cable", "diameter_mm": 0, "min_bend_radius_mm": 5})")),
      "'diameter_mm' must be > 0");
  has(what_of(with_element(R"({"name": "a", "kind": "cable", "diameter_mm": "5", "min_bend_radius_mm": 5})")),
      "number");
  has(what_of(with_element(R"({"name": "a", "kind": "cable", "diameter_mm": 5})")), "min_bend_ratio");
  has(what_of(with_element(R"({"name": "a", "kind": "cable", "diameter_mm": 5, "min_bend_radius_mm": 5,
                               "min_bend_ratio": 3})")), "not both");
  has(what_of(with_element(R"({"name": "a", "kind": "cable", "diameter_mm": 5, "min_bend_ratio": -3})")),
      "min_bend_ratio");
  has(what_of(with_element(R"({"name": "a", "kind": "cable", "diameter_mm": 5, "min_bend_ratio": 3,
                               "clearance_mm": -1})")), "clearance_mm");
  has(what_of(with_element(R"({"name": "a", "kind": "cable", "diameter_mm": 5, "min_bend_ratio": 3,
                               "bend_radius_reference": "outer"})")), "bend_radius_reference");
  has(what_of(with_element(R"({"name": "a", "kind": "cable", "diameter_mm": 5, "min_bend_ratio": 3,
                               "attached": "clamp"})")), "attached");
  has(what_of(with_element(R"({"name": "a", "kind": "cable", "diameter_mm": 5, "min_bend_ratio": 3,
                               "attached": ["a"]})")), "itself");
  has(what_of(with_element(R"({"name": "a", "kind": "rigid"}, {"name": "a", "kind": "rigid"})")), "twice");
  has(what_of(R"({"sensor": {"width_px": 0}, "elements": []})"), "width_px");
  has(what_of(R"({"sensor": {"width_px": 12.5}, "elements": []})"), "width_px");
  has(what_of(R"({"sensor": {"hfov_deg": 180}, "elements": []})"), "hfov_deg");
  has(what_of(R"({"sensor": {"standoff_mm": -1}, "elements": []})"), "standoff_mm");
  has(what_of(R"({"sensor": 3, "elements": []})"), "sensor");
  // The message names the element by name.
  has(what_of(with_element(R"({"name": "cable_Z", "kind": "cable", "diameter_mm": -1, "min_bend_ratio": 3})")),
      "cable_Z");
}

TEST(PlanFile, ReadFromDisk) {
  const InspectionPlan p = read_plan(write_bytes("plan.json", kContractPlan));
  EXPECT_EQ(p.elements.size(), 2u);
  EXPECT_THROW(read_plan(tmp_dir() + "/no_plan.json"), InputError);
  EXPECT_THROW(read_plan(write_bytes("empty_plan.json", "")), InputError);
  EXPECT_THROW(read_plan(tmp_dir()), InputError);
}
