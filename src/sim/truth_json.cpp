// truth.json (CONTRACT.md "ewis simulate", schema truth.schema.json) with extra fields: per-cable pieces,
// allowed radius, clearance, gaps to every neighbour, nominal measures, foreign object geometry, scan stats.
#include <cmath>
#include <nlohmann/json.hpp>

#include "ewis/sim/campaign.hpp"

namespace ewis::sim {

namespace {

using nlohmann::json;

double r4(double x) { return std::round(x * 1e4) / 1e4 + 0.0; }  // + 0.0: no "-0.0"
json vec(const Eigen::Vector3d& v) { return json::array({r4(v.x()), r4(v.y()), r4(v.z())}); }
json mat(const Eigen::Matrix4d& m) {
  json rows = json::array();
  for (int r = 0; r < 4; ++r) {
    json row = json::array();
    for (int c = 0; c < 4; ++c) row.push_back(m(r, c));  // full precision: this is the true pose
    rows.push_back(row);
  }
  return rows;
}
json radius_or_null(double r) { return std::isfinite(r) ? json(r4(r)) : json(nullptr); }

json piece_json(const RoutePiece& p) {
  json j;
  if (p.kind == RoutePiece::Kind::Straight) {
    j["kind"] = "straight";
    j["start"] = vec(p.start);
    j["end"] = vec(p.end);
  } else {
    j["kind"] = std::abs(p.b_mm) < 1e-12 ? "arc" : "helix";
    j["radius_mm"] = r4(p.curvature_radius_mm());
    j["helix_radius_mm"] = r4(p.a_mm);
    j["pitch_mm"] = r4(2.0 * M_PI * p.b_mm);
    j["angle_deg"] = r4(p.angle_rad * 180.0 / M_PI);
    j["center"] = vec(p.center);
    j["axis"] = vec(p.w);
  }
  j["length_mm"] = r4(p.length_mm());
  return j;
}

json shape_json(const Shape& s) {
  json j;
  const char* names[] = {"box", "sphere", "cylinder", "torus"};
  j["kind"] = names[static_cast<int>(s.kind)];
  j["frame"] = mat(s.frame.matrix());
  if (s.kind == Shape::Kind::Box) j["half_extents_mm"] = vec(s.half_extents_mm);
  if (s.kind != Shape::Kind::Box) j["radius_mm"] = r4(s.radius_mm);
  if (s.kind == Shape::Kind::Cylinder) j["length_mm"] = r4(s.length_mm);
  if (s.kind == Shape::Kind::Torus) j["major_radius_mm"] = r4(s.major_radius_mm);
  return j;
}

}  // namespace

std::string truth_to_json(const SimScene& sim, const Pose& camera_to_cad, const ScanResult* scan,
                          const SensorParams* sensor) {
  json t;
  t["camera_to_cad"] = mat(camera_to_cad.matrix());
  t["seed"] = sim.seed;
  t["requested_defect"] = defect_kind_name(sim.requested);
  t["view_target"] = vec(sim.view_target);
  json cables = json::array();
  for (const auto& c : sim.cables) {
    json j;
    j["name"] = c.name;
    j["diameter_mm"] = c.diameter_mm;
    j["length_mm"] = r4(c.as_built.length_mm());
    j["min_bend_radius_mm"] = radius_or_null(c.as_built.min_curvature_radius_mm());
    if (std::isfinite(c.as_built.min_curvature_radius_mm()))
      j["min_bend_location"] = vec(c.as_built.at(c.as_built.min_curvature_location_s()));
    j["allowed_bend_radius_mm"] = r4(c.allowed_bend_radius_mm);
    j["clearance_mm"] = c.clearance_mm;
    j["attached"] = c.attached;
    j["nominal_length_mm"] = r4(c.nominal.length_mm());
    j["nominal_min_bend_radius_mm"] = radius_or_null(c.nominal.min_curvature_radius_mm());
    json gaps = json::array();
    for (const auto& g : sim.gaps)
      if (g.cable == c.name) {
        json gj = {{"with", g.with_foreign ? json(nullptr) : json(g.with)},
                   {"element", g.with},
                   {"foreign", g.with_foreign},
                   {"gap_mm", r4(g.gap_mm)},
                   {"location", vec(g.location)},
                   {"ends", json::array({vec(g.on_cable_surface), vec(g.on_other_surface)})}};
        if (g.seen) gj["seen"] = *g.seen;
        gaps.push_back(gj);
      }
    j["gaps"] = gaps;
    json pieces = json::array();
    for (const auto& p : c.as_built.pieces) pieces.push_back(piece_json(p));
    j["pieces"] = pieces;
    json line = json::array();
    for (const auto& p : sample_route(c.as_built, 1.0)) line.push_back(vec(p));
    j["centerline"] = line;
    cables.push_back(j);
  }
  t["cables"] = cables;
  json defects = json::array();
  for (const auto& d : sim.defects) {
    json j;
    j["kind"] = d.kind;
    j["element"] = d.element;
    if (d.kind == "bend") {
      j["radius_mm"] = r4(d.radius_mm);
    } else {
      j["with"] = d.kind == "foreign_object" ? json(nullptr) : json(d.with);
      j["gap_mm"] = r4(d.gap_mm);
      j["ends"] = json::array({vec(d.on_cable_surface), vec(d.on_other_surface)});
      if (d.seen) j["seen"] = *d.seen;
    }
    j["location"] = vec(d.location);
    defects.push_back(j);
  }
  t["defects"] = defects;
  json foreign = json::array();
  for (const auto& r : sim.rigids)
    if (r.foreign) {
      json shapes = json::array();
      for (const auto& s : r.solid.shapes) shapes.push_back(shape_json(s));
      foreign.push_back({{"name", r.name}, {"shapes", shapes}});
    }
  t["foreign_objects"] = foreign;
  if (scan) {
    json s;
    s["points"] = scan->cloud.size();
    s["surface_points"] = scan->surface_points;
    s["outliers"] = scan->outliers;
    s["mismatched"] = scan->mismatched;
    s["camera_hits"] = scan->camera_hits;
    s["shadowed"] = scan->shadowed;
    s["grazing"] = scan->grazing;
    if (sensor) {
      s["sigma600_mm"] = sensor->noise_free ? 0.0 : sensor->sigma600_mm;
      s["outlier_fraction"] = sensor->noise_free ? 0.0 : sensor->outlier_fraction;
      s["mismatch_patches"] = sensor->noise_free ? 0 : sensor->mismatch_patches;
      s["baseline_mm"] = sensor->baseline_mm;
      s["max_incidence_deg"] = sensor->max_incidence_deg;
    }
    t["scan"] = s;
  }
  return t.dump(1) + "\n";
}

}  // namespace ewis::sim
