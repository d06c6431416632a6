// report.html: one self-contained page (inline CSS, base64 PNG pictures, no scripts, no external links).
#include "ewis/report/report_html.hpp"

#include <tbb/parallel_invoke.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include "ewis/core/parallel.hpp"
#include "ewis/report/pictures.hpp"

namespace ewis {

namespace {

std::string num(double v, int decimals) {
  if (!std::isfinite(v)) return "&ndash;";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}
std::string mm(double v, int decimals = 1) { return std::isfinite(v) ? num(v, decimals) + " mm" : "&ndash;"; }
std::string opt_mm(const std::optional<double>& v, int decimals = 1) { return v ? mm(*v, decimals) : "&ndash;"; }
std::string vec(const Eigen::Vector3d& p) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "(%.1f, %.1f, %.1f) mm", p.x(), p.y(), p.z());
  return buf;
}

std::string png_img(const Image& img, const std::string& alt, const std::string& cls) {
  return "<img class=\"" + cls + "\" width=\"" + std::to_string(img.width_px) + "\" height=\"" +
         std::to_string(img.height_px) + "\" alt=\"" + html_escape(alt) + "\" src=\"data:image/png;base64," +
         base64_encode(encode_png(img)) + "\">";
}

// A result cell: pass / fail / info (no rule) / n/a.
enum class Status { Pass, Fail, Info, NotApplicable };
std::string status_cell(Status s) {
  switch (s) {
    case Status::Pass: return "<td class=\"pass\">pass</td>";
    case Status::Fail: return "<td class=\"fail\">FAIL</td>";
    case Status::Info: return "<td class=\"info\">info</td>";
    default: return "<td class=\"na\">n/a</td>";
  }
}
Status from_opt(const std::optional<bool>& ok) { return ok ? (*ok ? Status::Pass : Status::Fail) : Status::NotApplicable; }

std::string swatch(const Rgb& c) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "<span class=\"sw\" style=\"background:#%02x%02x%02x\"></span>", c[0], c[1], c[2]);
  return buf;
}

bool cable_ok(const CableInspection& c) { return c.found && c.bend_ok != false && c.clearance_ok != false; }

const char* kCss = R"(body{font-family:"DejaVu Sans",Arial,Helvetica,sans-serif;margin:24px;color:#222;background:#fafafa}
h1{margin:0 0 6px 0;font-size:26px}h2{margin-top:28px;border-bottom:2px solid #ccc;padding-bottom:4px}
h3{margin:18px 0 6px 0}
.verdict{display:inline-block;padding:6px 18px;border-radius:6px;font-weight:bold;font-size:22px;color:#fff}
.vpass{background:#2e8b3a}.vfail{background:#c62828}
table{border-collapse:collapse;margin:8px 0;background:#fff}
th,td{border:1px solid #bbb;padding:4px 10px;text-align:left;font-size:14px}th{background:#e8e8e8}
td.num{text-align:right;font-variant-numeric:tabular-nums}
td.pass{background:#c8e6c9;color:#1b5e20;font-weight:bold}td.fail{background:#ffcdd2;color:#b71c1c;font-weight:bold}
td.info{background:#eceff1;color:#455a64}td.na{background:#f5f5f5;color:#888}
.meta{color:#555;font-size:14px}.sw{display:inline-block;width:14px;height:14px;border:1px solid #333;
vertical-align:middle;margin:0 4px 0 10px}.legend{font-size:14px;margin:6px 0}
img{border:1px solid #999;background:#fff;max-width:100%;height:auto}
figure{display:inline-block;margin:8px 16px 8px 0;vertical-align:top}figcaption{font-size:13px;color:#333;max-width:900px}
.pair img{margin-right:6px})";

void cable_section(std::ostringstream& o, const InspectionResult& r, std::size_t k) {
  const CableInspection& c = r.cables[k];
  o << "<h3>" << swatch(cable_color(k)) << html_escape(c.name) << " &mdash; "
    << (cable_ok(c) ? "<span style=\"color:#1b5e20\">pass</span>" : "<span style=\"color:#b71c1c\">FAIL</span>")
    << "</h3>\n<table>\n<tr><th>check</th><th>measured</th><th>allowed / nominal</th><th>result</th></tr>\n";
  o << "<tr><td>cable found in the scan</td><td>" << (c.found ? "yes" : "no") << "</td><td>required</td>"
    << status_cell(c.found ? Status::Pass : Status::Fail) << "</tr>\n";
  if (c.found) {
    o << "<tr><td>diameter</td><td class=\"num\">" << mm(c.diameter_mm, 2) << "</td><td class=\"num\">"
      << mm(c.nominal_diameter_mm, 2) << " (plan)</td>" << status_cell(Status::Info) << "</tr>\n";
    o << "<tr><td>measured length</td><td class=\"num\">" << mm(c.length_mm, 1) << "</td><td>&ndash;</td>"
      << status_cell(Status::Info) << "</tr>\n";
  }
  const bool inner = c.bend_reference == BendReference::Inner;
  const bool has_rule = c.allowed_bend_radius_mm > 0;
  std::string where = c.min_bend_location ? " at " + vec(*c.min_bend_location) : "";
  if (c.found && !c.min_bend_radius_mm) where = " (straight)";
  // the standard error tells a short, barely resolved bend (e.g. 15 deg over a few mm) from a well measured one
  const std::string se = c.min_bend_radius_mm && c.bend.min_radius_se_mm > 0
                             ? " &plusmn; " + mm(c.bend.min_radius_se_mm, 1)
                             : "";
  // an upper bound: a kink too short for its radius to be measured, at the loosest radius its points allow
  const std::string bound = c.min_bend_radius_mm && c.bend.min_radius_is_bound ? "&le; " : "";
  o << "<tr><td>min bend radius, 3D centreline</td><td class=\"num\">" << bound << opt_mm(c.min_bend_radius_mm) << se
    << (bound.empty() ? "" : " (a kink: upper bound; its best fit " + mm(c.bend.min_radius_fit_mm, 1) + ")")
    << (c.min_bend_radius_mm && std::string(c.bend.min_radius_model) == "smooth" ? " (peak of a smooth bend)" : "")
    << where
    << "</td><td class=\"num\">" << (!inner && has_rule ? "&ge; " + mm(c.allowed_bend_radius_mm) : "&ndash;") << "</td>"
    << status_cell(!inner && has_rule ? from_opt(c.bend_ok) : Status::Info) << "</tr>\n";
  o << "<tr><td>min bend radius, inner (centreline &minus; d/2)</td><td class=\"num\">"
    << opt_mm(c.min_bend_radius_inner_mm) << "</td><td class=\"num\">"
    << (inner && has_rule ? "&ge; " + mm(c.allowed_bend_radius_mm) : "&ndash;") << "</td>"
    << status_cell(inner && has_rule ? from_opt(c.bend_ok) : Status::Info) << "</tr>\n";
  o << "<tr><td>bend radius, paper 4.3.1 (projected, RANSAC circle)</td><td class=\"num\">"
    << (c.found ? opt_mm(c.paper_bend.radius_mm) : "&ndash;") << "</td><td>&ndash;</td>" << status_cell(Status::Info)
    << "</tr>\n";
  o << "<tr><td>clearance (surface to surface)</td><td class=\"num\">"
    << (c.found ? std::to_string(c.interferences.size()) + " interference" + (c.interferences.size() == 1 ? "" : "s") : "&ndash;")
    << "</td><td class=\"num\">&ge; " << mm(c.clearance_mm, 2) << "</td>" << status_cell(from_opt(c.clearance_ok))
    << "</tr>\n</table>\n";
  if (!c.interferences.empty()) {
    o << "<table>\n<tr><th>#</th><th>with</th><th>min distance</th><th>allowed</th><th>points</th><th>centre</th>"
         "<th>result</th></tr>\n";
    for (std::size_t i = 0; i < c.interferences.size(); ++i) {
      const Interference& f = c.interferences[i];
      o << "<tr><td>" << i + 1 << "</td><td>" << swatch(interference_color(!f.with))
        << (f.with ? html_escape(*f.with) : std::string("<i>foreign object (not in the CAD)</i>")) << "</td><td class=\"num\">"
        << mm(f.min_distance_mm, 2) << "</td><td class=\"num\">&ge; " << mm(c.clearance_mm, 2) << "</td><td class=\"num\">"
        << f.points.size() << "</td><td class=\"num\">" << vec(f.center) << "</td>" << status_cell(Status::Fail)
        << "</tr>\n";
    }
    o << "</table>\n";
  }
  if (c.found) {
    std::size_t bridged = 0;
    for (const SubCable& s : c.trace.segments) bridged += s.bridged;
    o << "<p class=\"meta\">chain: " << c.trace.segments.size() << " sub-cables (" << bridged
      << " bridged without data), " << c.trace.points.size() << " scan points, " << c.trace.gaps.size()
      << " gaps; allowed bend radius from the plan: " << (has_rule ? mm(c.allowed_bend_radius_mm) : "no rule")
      << ", measured to the " << (inner ? "inside of the bend" : "centreline") << ".</p>\n";
  }
}

}  // namespace

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char ch : text) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += ch;
    }
  }
  return out;
}

std::string report_html(const InspectionResult& r, const Scene& scene, const InspectionPlan& plan,
                        const ReportParams& params) {
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" << html_escape(params.title)
    << "</title>\n<style>\n" << kCss << "\n</style>\n</head>\n<body>\n";
  o << "<h1>" << html_escape(params.title) << "</h1>\n";
  o << "<p><span class=\"verdict " << (r.pass ? "vpass\">PASS" : "vfail\">FAIL") << "</span></p>\n";
  std::size_t failed = 0;
  for (const CableInspection& c : r.cables) failed += !cable_ok(c);
  o << "<p class=\"meta\">" << r.cables.size() << " cable" << (r.cables.size() == 1 ? "" : "s") << " inspected, "
    << failed << " failed" << (params.scan_name.empty() ? "" : "; scan " + html_escape(params.scan_name))
    << ". All coordinates are CAD coordinates (mm).</p>\n";

  // Overview: one row per cable, one column per rule.
  o << "<h2>Verdict per cable and rule</h2>\n<table>\n<tr><th>cable</th><th>found</th><th>bend radius</th>"
       "<th>clearance</th><th>cable verdict</th></tr>\n";
  for (std::size_t k = 0; k < r.cables.size(); ++k) {
    const CableInspection& c = r.cables[k];
    o << "<tr><td>" << swatch(cable_color(k)) << html_escape(c.name) << "</td>"
      << status_cell(c.found ? Status::Pass : Status::Fail) << status_cell(from_opt(c.bend_ok))
      << status_cell(from_opt(c.clearance_ok)) << status_cell(cable_ok(c) ? Status::Pass : Status::Fail) << "</tr>\n";
  }
  o << "</table>\n";

  const PointLabels labels = label_points(r);
  // The pictures: the scan, then each defect's pair, each a function of the result alone (the page is the same
  // for any thread count). The scan's picture first, alone (its full-size buffers); then its PNG encoding (one
  // thread) beside the close-ups (in parallel). (A ray caster built here, when the result holds none, comes after
  // the scan's full-size buffers are gone.)
  const std::vector<DefectView> views = defect_views(r, params.max_closeups);
  const bool render_cad = !views.empty() && params.render_cad && !scene.triangles.empty();
  const std::size_t per_view = render_cad ? 2 : 1;
  std::vector<std::string> img(1 + per_view * views.size());
  const Image scan_picture = splat_scan(r, labels, report_camera(plan, params.scan_image_width_px), r.scan_to_cad);
  const auto closeups = [&] {
    if (views.empty()) return;
    // The inspection's own when it is over this scene (the same BVH), else built here.
    std::shared_ptr<const Raycaster> caster;
    if (render_cad)
      caster = r.scene_caster && &r.scene_caster->scene() == &scene ? r.scene_caster
                                                                    : std::make_shared<const Raycaster>(scene);
    parallel_for_each_index(img.size() - 1, [&](std::size_t k) {
      const std::size_t v = k / per_view;
      const CloseupCamera cam = closeup_camera(r, views[v], params.closeup_width_px, params.closeup_height_px);
      img[1 + k] = k % per_view == 0
                       ? png_img(closeup_splat(r, labels, views[v], cam), "scan points around " + views[v].title,
                                 "closeup")
                       : png_img(closeup_render(r, labels, *caster, views[v], cam), "CAD around " + views[v].title,
                                 "closeup");
    }, 1);
  };
  tbb::parallel_invoke([&] { img[0] = png_img(scan_picture, "scan from the registered sensor pose", "scan"); },
                       closeups);

  // The scan as the sensor saw it.
  o << "<h2>The scan as the sensor saw it</h2>\n";
  {
    o << "<figure>" << img[0] << "\n<figcaption>"
      << r.cloud.size() << " filtered points seen from the registered sensor pose. <span class=\"legend\">";
    for (std::size_t k = 0; k < r.cables.size(); ++k) o << swatch(cable_color(k)) << html_escape(r.cables[k].name);
    o << swatch(interference_color(false)) << "interference (CAD element)" << swatch(interference_color(true))
      << "foreign object" << swatch(Rgb{150, 150, 150}) << "rest (grey by depth, light = near)"
      << swatch(Rgb{255, 255, 255}) << "chain axes (dashed: bridged gap)" << swatch(Rgb{255, 0, 255})
      << "ring: minimum bend radius below the rule</span></figcaption></figure>\n";
  }

  // Close-ups of each defect.
  o << "<h2>Defects</h2>\n";
  if (views.empty()) {
    o << "<p>No bend-radius or clearance defect to show" << (failed ? " (see the tables for cables not found)" : "")
      << ".</p>\n";
  } else {
    for (std::size_t v = 0; v < views.size(); ++v) {
      o << "<figure class=\"pair\">";
      for (std::size_t k = 0; k < per_view; ++k) o << img[1 + v * per_view + k];
      o << "\n<figcaption><b>" << v + 1 << ". " << html_escape(views[v].title) << "</b> &mdash; left: the scan points"
        << (render_cad ? "; right: the registered CAD (ray cast)" : "") << ", seen from the sensor, &plusmn;"
        << num(views[v].half_extent_mm, 0) << " mm around " << vec(views[v].target)
        << ". White lines: the measured chain axes; yellow: the measured gap; magenta: the fitted bend circle."
        << "</figcaption></figure>\n";
    }
  }

  o << "<h2>Cables</h2>\n";
  for (std::size_t k = 0; k < r.cables.size(); ++k) cable_section(o, r, k);

  o << "<h2>Scan and registration</h2>\n<table>\n";
  o << "<tr><td>scan points (input)</td><td class=\"num\">" << r.scan_points << "</td></tr>\n";
  o << "<tr><td>after radius outlier removal (paper 4.1.1)</td><td class=\"num\">" << r.filtered_points << " (r = "
    << mm(r.outlier_radius_mm, 2) << ", k = " << r.outlier_min_neighbors << ")</td></tr>\n";
  o << "<tr><td>resolution (median point spacing)</td><td class=\"num\">" << mm(r.resolution_mm, 3) << "</td></tr>\n";
  o << "<tr><td>registration RMSE (paper 4.1.2)</td><td class=\"num\">" << mm(r.registration_rmse_mm, 3) << "</td></tr>\n";
  o << "<tr><td>registration fitness</td><td class=\"num\">" << num(r.registration_fitness * 100.0, 1) << " %</td></tr>\n";
  if (r.registration_in_front_fraction >= 0)
    o << "<tr><td>CAD faces in front of the scan</td><td class=\"num\">"
      << num(r.registration_in_front_fraction * 100.0, 1) << " %</td></tr>\n";
  o << "<tr><td>converged</td><td>" << (r.registration_converged ? "yes" : "no")
    << (r.registration_global ? " (global registration, no initial pose used)" : " (from the initial pose)") << "</td></tr>\n";
  o << "<tr><td>sensor position</td><td class=\"num\">" << vec(r.sensor_position) << "</td></tr>\n";
  o << "<tr><td>scan points hidden behind others, seen from its origin</td><td class=\"num\">"
    << num(r.sensor_origin_occluded_fraction * 100.0, 1) << " %"
    << (r.sensor_at_scan_origin ? "" : " <b>(not in its sensor's frame: the results are not to be trusted)</b>")
    << "</td></tr>\n</table>\n";
  for (const std::string& w : r.warnings) o << "<p><b>Warning:</b> " << html_escape(w) << "</p>\n";
  if (params.include_timings && !r.timings.empty()) {
    o << "<h3>Time per step</h3>\n<table>\n<tr><th>step</th><th>seconds</th></tr>\n";
    double total = 0;
    for (const StepTiming& t : r.timings) {
      o << "<tr><td>" << html_escape(t.step) << "</td><td class=\"num\">" << num(t.seconds, 3) << " s</td></tr>\n";
      total += t.seconds;
    }
    o << "<tr><th>total</th><th>" << num(total, 3) << " s</th></tr>\n</table>\n";
  }
  o << "<p class=\"meta\">Written by ewis-inspect. Rules from the plan; bend radius: local circle fits along the "
       "measured centreline (3D) and the paper's projected figure; clearance: surface-to-surface gaps of the "
       "fitted cable to the other cable's model, the registered CAD surface, or a foreign object's points.</p>\n";
  o << "</body>\n</html>\n";
  return o.str();
}

}  // namespace ewis
