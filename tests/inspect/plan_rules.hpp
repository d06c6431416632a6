#pragma once
// A cable's entry of an inspection plan, for the inspect tests' scenes.
#include <string>

#include "ewis/io/plan_file.hpp"

namespace ewis::test {

inline PlanElement cable_rule(const std::string& name, double diameter_mm, double min_bend_radius_mm,
                              double clearance_mm) {
  PlanElement e;
  e.name = name;
  e.kind = ElementKind::Cable;
  e.diameter_mm = diameter_mm;
  e.min_bend_radius_mm = min_bend_radius_mm;
  e.clearance_mm = clearance_mm;
  return e;
}

}  // namespace ewis::test
