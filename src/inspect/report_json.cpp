// report.json of CONTRACT.md, written by hand so the number format is fixed (byte-identical output).
#include <cmath>
#include <cstdio>
#include <sstream>

#include "ewis/inspect/pipeline.hpp"

namespace ewis {
namespace {

std::string num(double v, int decimals) {
  if (!std::isfinite(v)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s = buf;
  if (s.find('.') != std::string::npos) {
    while (!s.empty() && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

std::string vec(const Eigen::Vector3d& v, int decimals = 3) {
  std::string s = "[";
  s += num(v.x(), decimals);
  s += ", ";
  s += num(v.y(), decimals);
  s += ", ";
  s += num(v.z(), decimals);
  s += "]";
  return s;
}

std::string opt_num(const std::optional<double>& v, int decimals = 3) { return v ? num(*v, decimals) : "null"; }
std::string opt_bool(const std::optional<bool>& v) { return v ? (*v ? "true" : "false") : "null"; }

std::string quote(const std::string& s) {
  std::string out = "\"";
  for (unsigned char ch : s) {
    switch (ch) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (ch < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", ch);
          out += buf;
        } else {
          out += char(ch);
        }
    }
  }
  return out + "\"";
}

void write_cable(std::ostringstream& o, const CableInspection& c) {
  const std::string in = "      ";
  o << "    {\n";
  o << in << "\"name\": " << quote(c.name) << ",\n";
  o << in << "\"kind\": \"cable\",\n";
  o << in << "\"found\": " << (c.found ? "true" : "false") << ",\n";
  o << in << "\"diameter_mm\": " << (c.found ? num(c.diameter_mm, 3) : "null") << ",\n";
  o << in << "\"length_mm\": " << (c.found ? num(c.length_mm, 2) : "null") << ",\n";
  o << in << "\"min_bend_radius_mm\": " << opt_num(c.min_bend_radius_mm, 2) << ",\n";
  o << in << "\"min_bend_radius_se_mm\": "
    << (c.min_bend_radius_mm ? num(c.bend.min_radius_se_mm, 2) : "null") << ",\n";
  // true: min_bend_radius_mm is an upper bound (a kink too short for its radius to be measured; bend_radius.hpp)
  o << in << "\"min_bend_radius_is_bound\": " << (c.min_bend_radius_mm && c.bend.min_radius_is_bound ? "true" : "false")
    << ",\n";
  // with the bound: the fit's radius under it (at least the tube's; InspectParams::bound_verdict_se), else null
  o << in << "\"min_bend_radius_fit_mm\": "
    << (c.min_bend_radius_mm && c.bend.min_radius_is_bound ? num(c.bend.min_radius_fit_mm, 2) : "null") << ",\n";
  // the model the figure comes from (bend_radius.hpp): circle, fillet, bound or smooth
  o << in << "\"min_bend_radius_model\": "
    << (c.min_bend_radius_mm ? std::string("\"") + c.bend.min_radius_model + "\"" : std::string("null")) << ",\n";
  o << in << "\"min_bend_radius_inner_mm\": " << opt_num(c.min_bend_radius_inner_mm, 2) << ",\n";
  o << in << "\"min_bend_location\": " << (c.min_bend_location ? vec(*c.min_bend_location, 2) : "null") << ",\n";
  o << in << "\"paper_bend_radius_mm\": " << opt_num(c.found ? c.paper_bend.radius_mm : std::nullopt, 2) << ",\n";
  o << in << "\"allowed_bend_radius_mm\": "
    << (c.allowed_bend_radius_mm > 0 ? num(c.allowed_bend_radius_mm, 3) : "null") << ",\n";
  o << in << "\"bend_radius_reference\": "
    << (c.bend_reference == BendReference::Inner ? "\"inner\"" : "\"centreline\"") << ",\n";
  o << in << "\"bend_ok\": " << opt_bool(c.bend_ok) << ",\n";
  o << in << "\"clearance_mm\": " << num(c.clearance_mm, 3) << ",\n";
  o << in << "\"interferences\": [";
  for (std::size_t i = 0; i < c.interferences.size(); ++i) {
    const Interference& f = c.interferences[i];
    o << (i ? ",\n" : "\n") << in << "  { \"with\": " << (f.with ? quote(*f.with) : "null")
      << ", \"min_distance_mm\": " << num(f.min_distance_mm, 3) << ", \"points\": " << f.points.size()
      << ", \"center\": " << vec(f.center, 2) << ", \"closest_on_cable\": " << vec(f.closest_on_cable, 2)
      << ", \"closest_on_other\": " << vec(f.closest_on_other, 2) << ", \"occluding_points\": " << f.occluding_points
      << " }";
  }
  if (!c.interferences.empty()) o << "\n" << in;
  o << "],\n";
  o << in << "\"clearance_ok\": " << opt_bool(c.clearance_ok) << ",\n";
  // where it forks, and parts of its CAD seen but not traced (a branch of another diameter): only when there are any
  for (const auto& [key, list] : {std::pair{"forks", &c.forks}, std::pair{"untraced_parts", &c.untraced_parts}}) {
    if (list->empty()) continue;
    o << in << "\"" << key << "\": [";
    for (std::size_t i = 0; i < list->size(); ++i) o << (i ? ", " : "") << vec((*list)[i], 2);
    o << "],\n";
  }
  // the share of its CAD its runs cover (InspectParams::min_traced_fraction)
  o << in << "\"cad_traced_fraction\": " << (c.found ? num(c.cad_traced_fraction, 3) : "null") << ",\n";
  o << in << "\"points\": " << (c.found ? c.trace.points.size() : 0) << ",\n";
  o << in << "\"segments\": [";
  if (c.found) {
    for (std::size_t i = 0; i < c.trace.segments.size(); ++i) {
      const SubCable& s = c.trace.segments[i];
      o << (i ? ",\n" : "\n") << in << "  { \"start\": " << vec(s.cylinder.start, 3) << ", \"end\": "
        << vec(s.cylinder.end, 3) << ", \"radius_mm\": " << num(std::max(s.cylinder.radius_mm, 1e-3), 3)
        << ", \"points\": " << s.points << " }";
    }
  }
  if (c.found && !c.trace.segments.empty()) o << "\n" << in;
  o << "],\n";
  o << in << "\"gaps\": [";
  if (c.found) {
    for (std::size_t i = 0; i < c.trace.gaps.size(); ++i)
      o << (i ? ", " : "") << "{ \"start\": " << vec(c.trace.gaps[i].start) << ", \"end\": " << vec(c.trace.gaps[i].end)
        << " }";
  }
  o << "]\n";
  o << "    }";
}

}  // namespace

std::string report_to_json(const InspectionResult& r, const InspectionPlan& plan) {
  std::ostringstream o;
  o << "{\n";
  o << "  \"verdict\": \"" << (r.pass ? "pass" : "fail") << "\",\n";
  o << "  \"registration\": {\n    \"transform\": [";
  const Eigen::Matrix4d m = (r.scan_to_cad * r.scan_to_sensor).matrix();  // (the scan as given)
  for (int i = 0; i < 4; ++i) {
    o << (i ? ", " : "") << "[";
    for (int j = 0; j < 4; ++j) o << (j ? ", " : "") << num(m(i, j), j == 3 ? 6 : 9);
    o << "]";
  }
  o << "],\n";
  o << "    \"rmse_mm\": " << num(std::max(0.0, r.registration_rmse_mm), 4) << ",\n";
  o << "    \"fitness\": " << num(r.registration_fitness, 4) << ",\n";
  o << "    \"converged\": " << (r.registration_converged ? "true" : "false") << ",\n";
  o << "    \"global\": " << (r.registration_global ? "true" : "false") << ",\n";
  o << "    \"in_front_fraction\": "
    << (r.registration_in_front_fraction >= 0 ? num(r.registration_in_front_fraction, 4) : std::string("null")) << "\n  },\n";
  o << "  \"scan\": { \"points\": " << r.scan_points << ", \"filtered_points\": " << r.filtered_points
    << ", \"resolution_mm\": " << num(r.resolution_mm, 4) << ", \"outlier_radius_mm\": " << num(r.outlier_radius_mm, 4)
    << ", \"outlier_min_neighbors\": " << r.outlier_min_neighbors
    << ", \"occluded_from_origin\": " << num(r.sensor_origin_occluded_fraction, 4)
    << ", \"sensor_frame\": " << (r.sensor_at_scan_origin ? "true" : "false")
    << ", \"noise_inflation\": " << num(r.noise.inflation, 2)
    << ", \"pixel_pitch_mrad\": " << (r.pixel_pitch_rad > 0 ? num(1e3 * r.pixel_pitch_rad, 4) : std::string("null"))
    << " },\n";
  o << "  \"elements\": [";
  // Plan order: cables and (when listed) rigid elements as the plan gives them.
  bool first = true;
  std::size_t ci = 0, ri = 0;
  for (const PlanElement& e : plan.elements) {
    if (e.kind == ElementKind::Cable) {
      if (ci >= r.cables.size()) continue;
      o << (first ? "\n" : ",\n");
      write_cable(o, r.cables[ci++]);
      first = false;
    } else {
      if (ri >= r.rigid.size() || r.rigid[ri].name != e.name) continue;
      const RigidInspection& rg = r.rigid[ri++];
      o << (first ? "\n" : ",\n") << "    { \"name\": " << quote(rg.name) << ", \"kind\": \"rigid\", \"points\": "
        << rg.points << " }";
      first = false;
    }
  }
  o << (first ? "]\n" : "\n  ]\n");
  o << "}\n";
  return o.str();
}

}  // namespace ewis
