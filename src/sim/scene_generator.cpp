// Scene generator (docs/sim.md): the as-built assembly is laid out first, the nominal CAD routes are derived
// from it (corners displaced a few mm, other radii), defects are injected, and the result is accepted only
// when every rule holds with a margin or is violated by a margin (SceneMargins), else the next attempt runs.
#include "ewis/sim/scene_generator.hpp"

#include <algorithm>
#include <cmath>

#include "ewis/core/error.hpp"
#include "rng.hpp"

namespace ewis::sim {

namespace {

using V3 = Eigen::Vector3d;
constexpr double kDeg = M_PI / 180.0;

struct HelixTail {
  V3 bend_toward = V3::UnitY();
  double a = 0, b = 0, angle = 0, straight = 15;
};

// A cable as corners + fillet radii (as built and nominal) and an optional helical tail.
struct CableDesign {
  SimCable cable;
  std::vector<V3> corners_ab, corners_nom;
  std::vector<double> radii_ab, radii_nom;
  std::optional<HelixTail> tail_ab, tail_nom;
};

std::optional<Route> realize(const std::vector<V3>& corners, const std::vector<double>& radii,
                             const std::optional<HelixTail>& tail) {
  auto route = fillet_route(corners, radii, 2.0);
  if (!route) return std::nullopt;
  if (tail) {
    if (!append_helix(*route, tail->bend_toward, tail->a, tail->b, tail->angle)) return std::nullopt;
    append_straight(*route, tail->straight);
  }
  return route;
}

bool realize(CableDesign& d) {
  auto ab = realize(d.corners_ab, d.radii_ab, d.tail_ab);
  auto nom = realize(d.corners_nom, d.radii_nom, d.tail_nom);
  if (!ab || !nom) return false;
  d.cable.as_built = *ab;
  d.cable.nominal = *nom;
  return true;
}

// Horizontal left normal of a direction.
V3 left_normal(const V3& d) {
  V3 n(-d.y(), d.x(), 0.0);
  return n.norm() > 1e-9 ? V3(n.normalized()) : V3::UnitY();
}

// Corners and radii of the route offset sideways by `offset` (left > 0) in the horizontal plane: mitred
// corners, concentric fillets (R -/+ offset), so runs and arcs stay exactly parallel when the route is level.
void offset_route(const std::vector<V3>& corners, const std::vector<double>& radii, double offset,
                  std::vector<V3>& out_corners, std::vector<double>& out_radii) {
  const std::size_t n = corners.size();
  out_corners.resize(n);
  out_radii = radii;
  for (std::size_t i = 0; i < n; ++i) {
    const V3 d1 = i > 0 ? V3((corners[i] - corners[i - 1]).normalized()) : V3((corners[1] - corners[0]).normalized());
    const V3 d2 = i + 1 < n ? V3((corners[i + 1] - corners[i]).normalized()) : d1;
    const V3 n1 = left_normal(d1), n2 = left_normal(d2);
    V3 m = n1 + n2;
    m = m.norm() > 1e-9 ? V3(m.normalized()) : n1;
    out_corners[i] = corners[i] + m * (offset / std::max(0.2, m.dot(n1)));
    if (i > 0 && i + 1 < n) {
      const bool turns_left = d1.cross(d2).z() > 0;
      out_radii[i] = radii[i] + (turns_left == (offset > 0) ? -std::abs(offset) : std::abs(offset));
    }
  }
}

double lerp_y_at_x(const std::vector<V3>& corners, double x, double& z_out) {
  for (std::size_t i = 0; i + 1 < corners.size(); ++i) {
    const double x0 = corners[i].x(), x1 = corners[i + 1].x();
    if ((x >= x0 && x <= x1) || (x <= x0 && x >= x1)) {
      const double t = std::abs(x1 - x0) > 1e-9 ? (x - x0) / (x1 - x0) : 0.0;
      z_out = corners[i].z() + t * (corners[i + 1].z() - corners[i].z());
      return corners[i].y() + t * (corners[i + 1].y() - corners[i].y());
    }
  }
  z_out = corners.front().z();
  return corners.front().y();
}

// Cable size and rules: diameters 3-30 mm, allowed bend 2.5-6 diameters (capped so thick cables fit).
SimCable make_cable_rules(Rng& rng, const std::string& name, double d_lo, double d_hi, double clear_lo,
                          double clear_hi) {
  SimCable c;
  c.name = name;
  c.diameter_mm = std::round(rng.uniform(d_lo, d_hi) * 10.0) / 10.0;
  const double ratio = std::round(rng.uniform(2.5, std::max(2.6, std::min(6.0, 110.0 / c.diameter_mm))) * 2.0) / 2.0;
  c.rule_as_ratio = rng.chance(0.5);
  c.allowed_bend_radius_mm = c.rule_as_ratio ? ratio * c.diameter_mm : std::round(ratio * c.diameter_mm);
  c.bend_ratio = ratio;
  c.clearance_mm = std::round(rng.uniform(clear_lo, clear_hi) * 2.0) / 2.0;
  return c;
}

// Clean fillet radii for the interior corners: 1.35-2 x allowed (nominal radii vary +-8% and must stay >= 1.2x).
std::vector<double> clean_radii(Rng& rng, const SimCable& c, std::size_t corners) {
  std::vector<double> r(corners, 0.0);
  const double lo = 1.35 * c.allowed_bend_radius_mm;
  const double hi = std::max(lo * 1.3, std::min(20.0 * c.diameter_mm, 220.0));
  for (std::size_t i = 1; i + 1 < corners; ++i) r[i] = rng.uniform(lo, std::min(hi, lo * 2.2));
  return r;
}

std::vector<double> nominal_radii(Rng& rng, const SimCable& c, const std::vector<double>& ab) {
  std::vector<double> r = ab;
  for (std::size_t i = 1; i + 1 < r.size(); ++i)
    r[i] = std::max(1.26 * c.allowed_bend_radius_mm, ab[i] * rng.uniform(0.92, 1.08));
  return r;
}

// Nominal corners: the as-built ones moved by a smooth random displacement (ends pinned: connectors).
std::vector<V3> nominal_corners(Rng& rng, const std::vector<V3>& ab, const V3& extra) {
  std::vector<V3> n = ab;
  for (std::size_t i = 1; i + 1 < n.size(); ++i) {
    const double az = rng.uniform(0, 2 * M_PI);
    n[i] += V3(std::cos(az), std::sin(az), 0.0) * rng.uniform(2.0, 8.0) + V3(0, 0, rng.uniform(-3.0, 3.0)) + extra;
  }
  return n;
}

// A connector box where a route ends (or starts): the cable enters it 8 mm deep. `side` spans the box across
// several cables (a harness connector) when not zero.
Shape connector_box(const V3& end, const V3& out_dir, double half_width, const V3& side, double side_half) {
  const double depth = 30.0, insert = 8.0;
  Pose f = Pose::Identity();
  const V3 z = out_dir.normalized();
  V3 x = side.norm() > 1e-9 ? V3(side - z * z.dot(side)) : V3(left_normal(z));
  if (x.norm() < 1e-9) x = V3::UnitX() - z * z.x();
  x.normalize();
  f.linear().col(0) = x;
  f.linear().col(1) = z.cross(x);
  f.linear().col(2) = z;
  f.translation() = end + z * (0.5 * depth - insert) + x * (side.norm() > 1e-9 ? side.norm() * 0.5 : 0.0);
  return make_box_shape(f, V3(half_width + side_half, half_width, 0.5 * depth));
}

// A clamp ring touching the cable at s (torus around the run) with a foot down to the plate.
std::vector<Shape> clamp_shapes(const Route& route, double s, double radius, double ring_mm) {
  const V3 p = route.at(s), t = route.tangent(s);
  std::vector<Shape> out;
  out.push_back(make_torus_shape(p, t, radius + ring_mm, ring_mm));
  const double top = p.z() - radius - ring_mm;
  if (top > 1.0) {
    const V3 n = left_normal(t);
    Pose f = Pose::Identity();
    const V3 th = V3(t.x(), t.y(), 0).norm() > 1e-6 ? V3(V3(t.x(), t.y(), 0).normalized()) : V3::UnitX();
    f.linear().col(0) = th;
    f.linear().col(1) = n;
    f.linear().col(2) = V3::UnitZ();
    f.translation() = V3(p.x(), p.y(), 0.5 * top);
    out.push_back(make_box_shape(f, V3(ring_mm, std::min(radius, 6.0), 0.5 * top)));
  }
  return out;
}

// A pipe along `dir` through `mid` (horizontal), resting on two saddles.
Solid pipe_solid(const V3& mid, const V3& dir, double half_length, double radius) {
  Solid s;
  s.shapes.push_back(make_cylinder_shape(mid - dir * half_length, mid + dir * half_length, radius));
  for (double k : {-0.6, 0.6}) {
    const V3 c = mid + dir * (k * half_length);
    Pose f = Pose::Identity();
    f.linear().col(0) = dir;
    f.linear().col(1) = V3::UnitZ().cross(dir);
    f.linear().col(2) = V3::UnitZ();
    f.translation() = V3(c.x(), c.y(), 0.5 * c.z());
    if (c.z() > 1.0) s.shapes.push_back(make_box_shape(f, V3(6.0, 0.7 * radius, 0.5 * c.z())));
  }
  return s;
}

// An L bracket standing on the plate whose upright face is parallel to the run at p (tangent t), `gap` from
// the cable's surface on side n.
Solid bracket_solid(const V3& p, const V3& t, const V3& n, double cable_radius, double gap, Rng& rng) {
  const double thick = rng.uniform(2.0, 4.0), half_len = rng.uniform(12.0, 25.0);
  const double height = p.z() + cable_radius + rng.uniform(5.0, 20.0);
  const V3 th = V3(t.x(), t.y(), 0).normalized();
  Pose f = Pose::Identity();
  f.linear().col(0) = th;
  f.linear().col(1) = n;
  f.linear().col(2) = V3::UnitZ();
  const V3 base = V3(p.x(), p.y(), 0.0) + n * (cable_radius + gap + thick);
  f.translation() = base + V3(0, 0, 0.5 * height);
  Solid s;
  s.shapes.push_back(make_box_shape(f, V3(half_len, thick, 0.5 * height)));
  f.translation() = base + n * (thick + 15.0) + V3(0, 0, 2.0);
  s.shapes.push_back(make_box_shape(f, V3(half_len, 15.0, 2.0)));
  return s;
}

struct Attempt {
  const SceneParams& params;
  Rng rng;
  DefectKind defect;
  std::string clearance_with;
};

bool acceptable(const SimScene& sim, const SceneParams& params, DefectKind defect, const std::string& with_kind) {
  const SceneMargins& m = params.margins;
  for (const auto& c : sim.cables) {
    const double r = c.as_built.min_curvature_radius_mm();
    if (std::isfinite(r) && r < m.clean_bend_factor * c.allowed_bend_radius_mm &&
        r > m.defect_bend_factor * c.allowed_bend_radius_mm)
      return false;
    if (r < c.diameter_mm) return false;  // not a physical cable
    // Every bend sweeps at least 12 deg: a bend radius is only measurable over some arc.
    for (const Route* route : {&c.as_built, &c.nominal})
      for (const auto& p : route->pieces)
        if (p.kind == RoutePiece::Kind::Helix && p.angle_rad < 12.0 * kDeg) return false;
    const double rn = c.nominal.min_curvature_radius_mm();
    if (std::isfinite(rn) && rn < m.clean_bend_factor * c.allowed_bend_radius_mm) return false;
  }
  for (const auto& g : sim.gaps) {
    const SimCable* c = nullptr;
    for (const auto& cc : sim.cables)
      if (cc.name == g.cable) c = &cc;
    if (g.gap_mm < c->clearance_mm + m.clean_gap_mm && g.gap_mm > c->clearance_mm - m.defect_gap_mm) return false;
    if (g.gap_mm < -1e-3) return false;  // interpenetration
  }
  bool has_requested = defect == DefectKind::None;
  for (const auto& d : sim.defects) {
    if (d.kind != defect_kind_name(defect)) return false;
    if (d.kind == "clearance" && !with_kind.empty()) {
      const bool is_cable = d.with.rfind("cable_", 0) == 0;
      if ((with_kind == "cable") != is_cable) return false;
      if (with_kind != "cable" && d.with.rfind(with_kind + "_", 0) != 0) return false;
    }
    has_requested = true;
  }
  if (defect == DefectKind::None && !sim.defects.empty()) return false;
  if (!has_requested) return false;
  // The CAD itself must satisfy every clearance (the design was right; the build deviates).
  for (std::size_t i = 0; i < sim.cables.size(); ++i) {
    const SimCable& c = sim.cables[i];
    const Tube t{&c.nominal, 0.5 * c.diameter_mm};
    const auto attached = [&](const std::string& n) {
      return std::find(c.attached.begin(), c.attached.end(), n) != c.attached.end();
    };
    for (const auto& r : sim.rigids)
      if (!r.foreign && !attached(r.name) && tube_solid_gap(t, r.solid).gap_mm < c.clearance_mm + 0.5) return false;
    for (std::size_t j = i + 1; j < sim.cables.size(); ++j) {
      const SimCable& o = sim.cables[j];
      const double g = tube_tube_gap(t, Tube{&o.nominal, 0.5 * o.diameter_mm}).gap_mm;
      if (g < std::max(c.clearance_mm, o.clearance_mm) + 0.5) return false;
    }
  }
  return true;
}

// Shifts a design's as-built corners by `delta` (all corners).
void shift_as_built(CableDesign& d, const V3& delta) {
  for (auto& c : d.corners_ab) c += delta;
}

std::optional<SimScene> try_scene(const SceneParams& params, std::uint64_t attempt_seed, DefectKind defect,
                                  const std::string& with_kind) {
  Rng rng(attempt_seed);
  SimScene sim;
  sim.sensor = params.sensor;
  const int n_cables = params.cables > 0 ? std::clamp(params.cables, 1, 3)
                                         : (with_kind == "cable" ? rng.integer(2, 3) : rng.integer(1, 3));
  if (with_kind == "cable" && n_cables < 2) return std::nullopt;
  int n_pipes = params.pipes >= 0 ? std::clamp(params.pipes, 0, 2) : rng.integer(0, 2);
  if (with_kind == "pipe") n_pipes = std::max(n_pipes, 1);
  const bool want_cross = n_cables == 3 || (n_cables == 2 && (with_kind == "cable" || rng.chance(0.5)));
  const bool want_parallel = n_cables == 3 || (n_cables == 2 && !want_cross);

  // --- base structure: plate, two ribs, a block (registration needs more than a plane) ---
  SimRigid structure;
  structure.name = "structure";
  structure.solid.shapes.push_back(make_aabb_shape(V3(-300, -240, -6), V3(300, 240, 0)));
  structure.solid.shapes.push_back(make_aabb_shape(V3(-300, -240, 0), V3(300, -226, rng.uniform(25, 40))));
  structure.solid.shapes.push_back(make_aabb_shape(V3(286, -226, 0), V3(300, 240, rng.uniform(35, 50))));
  const double bx = rng.uniform(-290, -240), by = rng.uniform(150, 180);
  structure.solid.shapes.push_back(make_aabb_shape(V3(bx, by, 0), V3(bx + 50, by + 50, rng.uniform(40, 70))));
  sim.rigids.push_back(structure);

  // --- cable A: corners left to right, some corners raised (non-planar route) ---
  CableDesign A;
  const bool small_clear = want_parallel;
  // The defaults' draws are made with or without SceneParams::cable_diameter_mm (the same scenes without it).
  const auto diameters = [&](double lo, double hi) {
    return params.cable_diameter_mm ? *params.cable_diameter_mm : std::pair<double, double>(lo, hi);
  };
  const auto [a_lo, a_hi] = diameters(4.0, rng.chance(0.25) ? 30.0 : 14.0);
  A.cable = make_cable_rules(rng, "cable_A", a_lo, a_hi, small_clear ? 1.0 : 2.5, small_clear ? 2.0 : 6.0);
  const double rA = 0.5 * A.cable.diameter_mm;
  const double zA = 45.0 + rA + rng.uniform(0.0, 20.0);
  const int n_int = rng.integer(2, 3);
  const bool tail = !want_parallel && rng.chance(0.4);
  HelixTail tail_ab;
  if (tail) {
    tail_ab.a = rng.uniform(1.4, 1.8) * A.cable.allowed_bend_radius_mm;
    tail_ab.angle = rng.uniform(50.0, 100.0) * kDeg;
    tail_ab.b = rng.uniform(15.0, 35.0) / tail_ab.angle;
  }
  const double x0 = -235.0 + rng.uniform(0, 20), x1 = 235.0 - rng.uniform(0, 20) - (tail ? tail_ab.a + 30.0 : 0.0);
  A.corners_ab.push_back(V3(x0, rng.uniform(-70, 70), zA));
  for (int k = 1; k <= n_int; ++k) {
    const double x = x0 + (x1 - x0) * k / (n_int + 1) + rng.uniform(-20, 20);
    const double y = std::clamp(A.corners_ab.back().y() + rng.uniform(-130, 130), -150.0, 150.0);
    const double z = zA + (rng.chance(0.35) ? rng.uniform(10.0, 30.0) : 0.0);
    A.corners_ab.push_back(V3(x, y, z));
  }
  A.corners_ab.push_back(V3(x1, rng.uniform(-70, 70), zA));
  A.radii_ab = clean_radii(rng, A.cable, A.corners_ab.size());
  A.radii_nom = nominal_radii(rng, A.cable, A.radii_ab);
  if (tail) {
    const V3 t_end = (A.corners_ab.back() - A.corners_ab[A.corners_ab.size() - 2]).normalized();
    tail_ab.bend_toward = left_normal(t_end) * (rng.chance(0.5) ? 1.0 : -1.0);
    const V3 u = -tail_ab.bend_toward;
    if (t_end.cross(u).z() > 0) tail_ab.b = -tail_ab.b;  // rise upward (see append_helix: w_z = -a m_z / L)
    A.tail_ab = tail_ab;
    HelixTail tn = tail_ab;
    tn.a *= rng.uniform(0.96, 1.04);
    tn.b *= rng.uniform(0.9, 1.1);
    tn.angle *= rng.uniform(0.97, 1.03);
    A.tail_nom = tn;
  }

  // Defect bookkeeping: an away-displacement applied to the nominal corners of the cable(s) at fault.
  V3 nominal_shift_A = V3::Zero(), nominal_shift_B = V3::Zero();

  // Bend defect: one as-built fillet of A tighter than allowed (the nominal one stays clean).
  if (defect == DefectKind::Bend) {
    const int k = rng.integer(1, static_cast<int>(A.corners_ab.size()) - 2);
    const double f = rng.uniform(std::max(0.5, A.cable.diameter_mm / A.cable.allowed_bend_radius_mm), 0.8);
    A.radii_ab[k] = f * A.cable.allowed_bend_radius_mm;
  }

  // --- cable C: parallel beside A (a harness bundle; shares A's connectors and clamps) ---
  std::optional<CableDesign> C;
  double offset_C = 0.0;
  if (want_parallel) {
    CableDesign c;
    const auto [lo, hi] = diameters(3.0, std::min(16.0, A.cable.diameter_mm + 6.0));
    c.cable = make_cable_rules(rng, "cable_C", lo, hi, 1.0, 2.0);
    const double gap = std::max(A.cable.clearance_mm, c.cable.clearance_mm) + 2.0 + rng.uniform(0.8, 3.0);
    offset_C = (rng.chance(0.5) ? 1.0 : -1.0) * (rA + 0.5 * c.cable.diameter_mm + gap);
    c.radii_ab.clear();
    offset_route(A.corners_ab, A.radii_ab, offset_C, c.corners_ab, c.radii_ab);
    C = c;
  }

  // --- cable B: crossing over A (and C) along y ---
  std::optional<CableDesign> B;
  if (want_cross) {
    CableDesign b;
    const auto [lo, hi] = diameters(3.0, 16.0);
    b.cable = make_cable_rules(rng, "cable_B", lo, hi, 1.5, 4.0);
    const double xc = rng.uniform(-110, 110);
    double zc = 0;
    const double yc = lerp_y_at_x(A.corners_ab, xc, zc);
    const double zB = zc + 30.0 + rA + 0.5 * b.cable.diameter_mm + 20.0;
    const auto side = [&]() { return (rng.chance(0.5) ? 1.0 : -1.0) * rng.uniform(60.0, 110.0); };
    const double lean = rng.uniform(-25.0, 25.0);
    b.corners_ab = {V3(xc + side(), -205, zB - rng.uniform(0, 15)),
                    V3(xc - lean, yc - rng.uniform(60, 80), zB),
                    V3(xc + lean, yc + rng.uniform(60, 80), zB),
                    V3(xc + side(), 205, zB - rng.uniform(0, 15))};
    if (b.corners_ab[1].y() < -180 || b.corners_ab[2].y() > 180) return std::nullopt;
    b.radii_ab = clean_radii(rng, b.cable, b.corners_ab.size());
    B = b;
  }

  // --- clearance defect targets decided now (they need the nominal shift before realising) ---
  std::string target = with_kind;
  if (defect == DefectKind::Clearance && target.empty()) {
    std::vector<std::string> options = {"bracket"};
    if (n_pipes > 0) options.push_back("pipe");
    if (B) options.push_back("cable");
    target = options[rng.integer(0, static_cast<int>(options.size()) - 1)];
  }
  if (defect == DefectKind::Clearance && target == "cable" && !B) return std::nullopt;
  const double defect_gap =
      defect == DefectKind::Clearance || defect == DefectKind::ForeignObject ? rng.uniform(0.0, 1.0) : 0.0;

  // Realise A, C (as built) and B; the nominal corners come after the defect geometry is known.
  A.corners_nom = nominal_corners(rng, A.corners_ab, V3::Zero());
  if (!realize(A)) return std::nullopt;
  std::vector<V3> a_nom_corners = A.corners_nom;
  if (C) {
    offset_route(A.corners_nom, A.radii_nom, offset_C, C->corners_nom, C->radii_nom);
    if (!realize(*C)) return std::nullopt;
  }
  if (B) {
    // Crossing height: a clean gap of clearance + 2 + [0.5, 8] mm, or the defect gap; B shifted vertically.
    const double clear_max = std::max({A.cable.clearance_mm, B->cable.clearance_mm, C ? C->cable.clearance_mm : 0.0});
    const double want = (defect == DefectKind::Clearance && target == "cable")
                            ? defect_gap * (std::min(A.cable.clearance_mm, B->cable.clearance_mm) - 1.0)
                            : clear_max + 2.0 + rng.uniform(0.5, 8.0);
    for (int it = 0; it < 4; ++it) {
      B->corners_nom = B->corners_ab;
      B->radii_nom = B->radii_ab;
      if (!realize(*B)) return std::nullopt;
      double g = tube_tube_gap({&B->cable.as_built, 0.5 * B->cable.diameter_mm}, {&A.cable.as_built, rA}).gap_mm;
      if (C)
        g = std::min(g, tube_tube_gap({&B->cable.as_built, 0.5 * B->cable.diameter_mm},
                                      {&C->cable.as_built, 0.5 * C->cable.diameter_mm}).gap_mm);
      if (std::abs(g - want) < 1e-4) break;
      shift_as_built(*B, V3(0, 0, want - g));
    }
    // The nominal route (the CAD) from the final as-built one; over the crossing it runs higher when the
    // build brought the cables too close.
    if (defect == DefectKind::Clearance && target == "cable")
      nominal_shift_B = V3(0, 0, A.cable.clearance_mm + B->cable.clearance_mm + 4.0);
    B->corners_nom = nominal_corners(rng, B->corners_ab, nominal_shift_B);
    B->radii_nom = nominal_radii(rng, B->cable, B->radii_ab);
    if (!realize(*B)) return std::nullopt;
  }

  // --- pipes: lying low across the scene, below the cables ---
  for (int p = 0; p < n_pipes; ++p) {
    const double rp = rng.uniform(5.0, 14.0);
    const double ang = (90.0 + rng.uniform(-35, 35)) * kDeg;
    const V3 dir(std::cos(ang), std::sin(ang), 0.0);
    V3 mid(rng.uniform(-170, 170), rng.uniform(-30, 30), rp + 3.0);
    SimRigid pipe;
    pipe.name = "pipe_" + std::to_string(p + 1);
    const bool is_target = defect == DefectKind::Clearance && target == "pipe" && p == 0;
    if (is_target) {
      // Raised under A until the as-built gap is the defect gap.
      const double want = defect_gap * (A.cable.clearance_mm - 1.0);
      for (int it = 0; it < 6; ++it) {
        const double g = tube_solid_gap({&A.cable.as_built, rA}, pipe_solid(mid, dir, 200.0, rp)).gap_mm;
        if (std::abs(g - want) < 1e-4) break;
        mid.z() += g - want;
      }
      nominal_shift_A = V3(0, 0, A.cable.clearance_mm + 4.0);
    }
    pipe.solid = pipe_solid(mid, dir, 200.0, rp);
    sim.rigids.push_back(pipe);
  }

  // --- brackets beside a run of A (one may be the clearance target) ---
  const int n_brackets = rng.integer(1, 2) + (target == "bracket" ? 0 : 0);
  for (int k = 0; k < n_brackets; ++k) {
    const Route& r = A.cable.as_built;
    // A straight run of A long enough for the upright.
    std::vector<std::size_t> runs;
    double s0 = 0;
    std::vector<double> starts;
    for (std::size_t i = 0; i < r.pieces.size(); ++i) {
      starts.push_back(s0);
      if (r.pieces[i].kind == RoutePiece::Kind::Straight && r.pieces[i].length_mm() > 70.0 && i > 0 &&
          i + 1 < r.pieces.size())
        runs.push_back(i);
      s0 += r.pieces[i].length_mm();
    }
    if (runs.empty()) return std::nullopt;
    const std::size_t i = runs[rng.integer(0, static_cast<int>(runs.size()) - 1)];
    const double s = starts[i] + r.pieces[i].length_mm() * rng.uniform(0.35, 0.65);
    const V3 p = r.at(s), t = r.tangent(s);
    double side = rng.chance(0.5) ? 1.0 : -1.0;
    if (C) side = offset_C > 0 ? -1.0 : 1.0;  // away from the bundle's other cable
    const V3 n = left_normal(t) * side;
    const bool is_target = defect == DefectKind::Clearance && target == "bracket" && k == 0;
    const double gap = is_target ? defect_gap * (A.cable.clearance_mm - 1.0)
                                 : A.cable.clearance_mm + 2.0 + rng.uniform(2.0, 25.0);
    SimRigid br;
    br.name = "bracket_" + std::to_string(k + 1);
    br.solid = bracket_solid(p, t, n, rA, gap, rng);
    if (is_target) nominal_shift_A = -n * (A.cable.clearance_mm + 4.0);
    sim.rigids.push_back(br);
  }

  // Nominal corners of A (and the bundle's C) moved away from a clearance target: the CAD was right.
  if (nominal_shift_A.norm() > 0) {
    for (std::size_t i = 1; i + 1 < A.corners_nom.size(); ++i) A.corners_nom[i] = a_nom_corners[i] + nominal_shift_A;
    if (!realize(A)) return std::nullopt;
    if (C) {
      offset_route(A.corners_nom, A.radii_nom, offset_C, C->corners_nom, C->radii_nom);
      if (!realize(*C)) return std::nullopt;
    }
  }

  // --- clamps and connectors (attached) ---
  int clamp_no = 0, connector_no = 0;
  const auto add_clamp = [&](CableDesign& d, CableDesign* partner) {
    const Route& r = d.cable.as_built;
    double s0 = 0;
    std::vector<double> cand;
    for (const auto& piece : r.pieces) {
      if (piece.kind == RoutePiece::Kind::Straight && piece.length_mm() > 40.0) cand.push_back(s0 + 0.5 * piece.length_mm());
      s0 += piece.length_mm();
    }
    if (cand.empty()) return;
    const double s = cand[rng.integer(0, static_cast<int>(cand.size()) - 1)];
    SimRigid clamp;
    clamp.name = "clamp_" + std::to_string(++clamp_no);
    const double ring = rng.uniform(1.5, 3.0);
    for (const auto& sh : clamp_shapes(r, s, 0.5 * d.cable.diameter_mm, ring)) clamp.solid.shapes.push_back(sh);
    if (partner) {
      // The bundle's clamp holds both cables: a ring around the partner at its closest point.
      const V3 p = r.at(s);
      const Route& pr = partner->cable.as_built;
      double best = 1e300, bs = 0;
      for (double x = 0; x <= pr.length_mm(); x += 0.5)
        if ((pr.at(x) - p).squaredNorm() < best) {
          best = (pr.at(x) - p).squaredNorm();
          bs = x;
        }
      for (const auto& sh : clamp_shapes(pr, bs, 0.5 * partner->cable.diameter_mm, ring)) clamp.solid.shapes.push_back(sh);
      partner->cable.attached.push_back(clamp.name);
    }
    d.cable.attached.push_back(clamp.name);
    sim.rigids.push_back(clamp);
  };
  const auto add_connectors = [&](CableDesign& d, CableDesign* partner, double partner_offset) {
    const Route& r = d.cable.as_built;
    const double hw = 0.5 * std::max(d.cable.diameter_mm, partner ? partner->cable.diameter_mm : 0.0) + 5.0;
    for (int end = 0; end < 2; ++end) {
      const V3 p = end == 0 ? r.start() : r.end();
      const V3 out = end == 0 ? V3(-r.tangent(0.0)) : V3(r.tangent(r.length_mm()));
      V3 side = V3::Zero();
      if (partner) {
        const V3 q = end == 0 ? partner->cable.as_built.start() : partner->cable.as_built.end();
        side = q - p;
      }
      SimRigid con;
      con.name = "connector_J" + std::to_string(++connector_no);
      con.solid.shapes.push_back(connector_box(p, out, hw, side, 0.5 * std::abs(partner_offset)));
      d.cable.attached.push_back(con.name);
      if (partner) partner->cable.attached.push_back(con.name);
      sim.rigids.push_back(con);
    }
  };
  add_clamp(A, C ? &*C : nullptr);
  if (rng.chance(0.5)) add_clamp(A, C ? &*C : nullptr);
  add_connectors(A, C ? &*C : nullptr, offset_C);
  if (B) {
    add_connectors(*B, nullptr, 0.0);
    // B's clamp on an outer run, away from the crossing.
    const Route& r = B->cable.as_built;
    const double s = std::min(35.0, 0.3 * r.pieces.front().length_mm());
    SimRigid clamp;
    clamp.name = "clamp_" + std::to_string(++clamp_no);
    for (const auto& sh : clamp_shapes(r, s + 20.0, 0.5 * B->cable.diameter_mm, rng.uniform(1.5, 3.0)))
      clamp.solid.shapes.push_back(sh);
    B->cable.attached.push_back(clamp.name);
    sim.rigids.push_back(clamp);
  }

  // --- foreign object on the camera side of a cable ---
  if (defect == DefectKind::ForeignObject) {
    CableDesign& d = (B && rng.chance(0.3)) ? *B : A;
    const Route& r = d.cable.as_built;
    const double s = r.length_mm() * rng.uniform(0.25, 0.75);
    const V3 p = r.at(s), t = r.tangent(s);
    const double tilt = rng.uniform(-50.0, 50.0) * kDeg;
    V3 n = std::cos(tilt) * V3::UnitZ() + std::sin(tilt) * left_normal(t);
    n = (n - t * t.dot(n)).normalized();
    const double rc = 0.5 * d.cable.diameter_mm;
    const double gap = rng.chance(0.3) ? 0.0 : defect_gap * (d.cable.clearance_mm - 1.0);
    SimRigid fo;
    fo.name = "foreign_1";
    fo.foreign = true;
    const int type = rng.integer(0, 2);
    if (type == 0) {
      const double R = rng.uniform(3.0, 8.0);
      fo.solid.shapes.push_back(make_sphere_shape(p + n * (rc + gap + R), R));
    } else {
      // A box (type 1) or a zip-tie-like bar across the cable (type 2), one face toward the cable.
      const V3 across = t.cross(n).normalized();
      const double spin = type == 1 ? rng.uniform(0.0, 90.0) * kDeg : 0.0;
      Pose f = Pose::Identity();
      const V3 x = std::cos(spin) * across + std::sin(spin) * t;
      f.linear().col(0) = x;
      f.linear().col(1) = n.cross(x);
      f.linear().col(2) = n;
      const V3 h = type == 1 ? V3(rng.uniform(3, 8), rng.uniform(3, 8), rng.uniform(3, 6))
                             : V3(rng.uniform(14, 20), rng.uniform(1.5, 2.5), rng.uniform(0.8, 1.5));
      f.translation() = p + n * (rc + gap + h.z());
      fo.solid.shapes.push_back(make_box_shape(f, h));
    }
    sim.rigids.push_back(fo);
  }

  sim.cables.push_back(A.cable);
  if (B) sim.cables.push_back(B->cable);
  if (C) sim.cables.push_back(C->cable);
  std::sort(sim.cables.begin(), sim.cables.end(), [](const SimCable& a, const SimCable& b) { return a.name < b.name; });
  measure_scene(sim);
  if (!acceptable(sim, params, defect, defect == DefectKind::Clearance ? target : std::string())) return std::nullopt;

  // --- the true sensor pose: ~600 mm from the cables' region, up to 30 deg off the plate normal ---
  V3 lo = V3::Constant(1e300), hi = V3::Constant(-1e300);
  for (const auto& c : sim.cables)
    for (const auto& q : sample_route(c.as_built, 5.0)) {
      lo = lo.cwiseMin(q);
      hi = hi.cwiseMax(q);
    }
  sim.view_target = 0.5 * (lo + hi);
  const double tilt = params.view_tilt_max_deg * std::sqrt(rng.uniform()) * kDeg, az = rng.uniform(0, 2 * M_PI);
  const V3 dir(std::sin(tilt) * std::cos(az), std::sin(tilt) * std::sin(az), std::cos(tilt));
  const double dist = params.sensor.standoff_mm + rng.uniform(-1.0, 1.0) * params.standoff_tolerance_mm;
  const double roll = rng.uniform(0, 2 * M_PI);
  sim.camera_to_cad = look_at(sim.view_target + dir * dist, sim.view_target, V3(std::cos(roll), std::sin(roll), 0.0));
  return sim;
}

}  // namespace

SimScene generate_scene(const SceneParams& params) {
  Rng pick(mix(params.seed, 0, 7));
  DefectKind defect = params.defect;
  if (defect == DefectKind::Random) {
    const DefectKind kinds[] = {DefectKind::Bend, DefectKind::Clearance, DefectKind::ForeignObject};
    defect = kinds[pick.integer(0, 2)];
  }
  std::string with = params.clearance_with;
  for (int a = 0; a < std::max(1, params.max_attempts); ++a) {
    auto sim = try_scene(params, mix(params.seed, static_cast<std::uint64_t>(a), 11), defect, with);
    if (sim) {
      sim->seed = params.seed;
      sim->requested = defect;
      sim->attempts = a + 1;
      return *sim;
    }
  }
  throw ProcessingError("simulate: no valid scene found for seed " + std::to_string(params.seed) + " in " +
                        std::to_string(params.max_attempts) + " attempts");
}

}  // namespace ewis::sim
