// The online inspection, wired step by step (paper 4): each step is a call into its stage.
#include "ewis/inspect/pipeline.hpp"

#include <algorithm>
#include <cstdio>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <string_view>

#include "ewis/core/error.hpp"
#include "ewis/core/parallel.hpp"
#include "ewis/core/robust.hpp"
#include "ewis/filter/pixel_pitch.hpp"
#include "ewis/filter/resolution.hpp"
#include "ewis/inspect/chain_distance.hpp"
#include "ewis/inspect/fillet_fit.hpp"
#include "ewis/inspect/run_conflicts.hpp"
#include "ewis/inspect/run_joins.hpp"
#include "ewis/inspect/surface_clumps.hpp"
#include "ewis/scene/surface_index.hpp"
#include "ewis/raycast/raycaster.hpp"
#include "ewis/register/sensor_origin.hpp"
#include "ewis/core/scratch.hpp"
#include "ewis/search/spatial_sort.hpp"
#include "ewis/sample/mesh_sampling.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis {
namespace {

// A CAD sample is seen when the sensor's ray to it hits nothing more than this before it.
constexpr float kSeenToleranceMm = 0.5f;

class StepClock {
 public:
  explicit StepClock(std::vector<StepTiming>& out) : out_(out), t0_(std::chrono::steady_clock::now()) {}
  void lap(const std::string& step) {
    const auto t = std::chrono::steady_clock::now();
    out_.push_back({step, std::chrono::duration<double>(t - t0_).count()});
    t0_ = t;
  }

 private:
  std::vector<StepTiming>& out_;
  std::chrono::steady_clock::time_point t0_;
};

bool inside_box(const Eigen::Vector3d& p, const Element& e, double margin) {
  return (p.array() >= e.bounds_min.array() - margin).all() && (p.array() <= e.bounds_max.array() + margin).all();
}

}  // namespace

void check_plan_against_scene(const InspectionPlan& plan, const Scene& scene, const std::string& plan_path) {
  for (const PlanElement& e : plan.elements) {
    if (scene.find(e.name) < 0) throw InputError(plan_path, "element '" + e.name + "' is not in the CAD scene");
    for (const std::string& a : e.attached) {
      if (scene.find(a) < 0)
        throw InputError(plan_path, "element '" + e.name + "' is attached to '" + a + "', which is not in the CAD scene");
      if (a == e.name) throw InputError(plan_path, "element '" + e.name + "' lists itself as attached");
    }
  }
}

void check_cad_units(const InspectionPlan& plan, const Scene& scene, const std::string& cad_path) {
  std::string thinnest;  // the first cable's figures, for the message
  int cables = 0, thin = 0;
  for (const PlanElement& e : plan.elements) {
    const int idx = scene.find(e.name);
    if (e.kind != ElementKind::Cable || idx < 0 || !(e.diameter_mm > 0)) continue;
    const Element& el = scene.elements[std::size_t(idx)];
    if (el.triangle_count == 0) continue;
    ++cables;
    const double least = (el.bounds_max - el.bounds_min).minCoeff();
    if (!(least < 0.5 * e.diameter_mm)) continue;
    if (++thin == 1) {
      char text[200];
      std::snprintf(text, sizeof text, "%s is %.3g mm across in the CAD for a %.3g mm diameter in the plan",
                    e.name.c_str(), least, e.diameter_mm);
      thinnest = text;
    }
  }
  if (cables > 0 && thin == cables)
    throw InputError(cad_path, thinnest + ": the CAD looks like metres or inches; CAD coordinates are millimetres");
}

OrientationRepair orient_rigid_faces(Scene& scene, const InspectionPlan& plan) {
  std::vector<bool> rigid(scene.elements.size(), true);
  for (const PlanElement& e : plan.elements)
    if (e.kind == ElementKind::Cable) {
      const int idx = scene.find(e.name);
      if (idx >= 0) rigid[std::size_t(idx)] = false;
    }
  return orient_faces_outward(scene, rigid);
}

InspectionResult inspect(const Scene& scene, const InspectionPlan& plan, Cloud scan,
                         const std::optional<Pose>& initial_scan_to_cad, const InspectParams& params,
                         const ProgressFn& progress) {
  InspectionResult res;
  StepClock clock(res.timings);
  // Cables are traced, measured and checked in parallel: progress may come from any thread.
  std::mutex progress_mutex;
  auto report = [&](const char* stage, double f) {
    if (!progress) return;
    const std::lock_guard<std::mutex> lock(progress_mutex);
    progress(stage, f);
  };
  // Runs body(c) for every cable at once (each cable's work is its own, so the results are those of one at a
  // time), reporting the stage's progress as cables finish, up to `span` of the stage.
  const auto each_cable = [&](std::size_t n, const char* stage, double span, const auto& body) {
    std::size_t done = 0;  // under progress_mutex
    report(stage, 0.0);
    parallel_for_each_index(n, [&](std::size_t c) {
      body(c);
      const std::lock_guard<std::mutex> lock(progress_mutex);
      ++done;
      if (progress) progress(stage, span * double(done) / double(n));
    }, 1);
  };
  res.scan_points = scan.size();
  if (scan.empty()) throw ProcessingError("the scan has no points");
  // A CAD wound inside out, or against itself, was turned outward when it was read (scene/orient_faces.hpp): said,
  // since which way a face looks decides what the registration matches it with.
  {
    std::size_t triangles = 0, elements = 0;
    std::string names;
    for (const Element& e : scene.elements) {
      if (e.reoriented_triangles == 0) continue;
      triangles += e.reoriented_triangles;
      if (++elements <= 4) names += (names.empty() ? "" : ", ") + e.name;
    }
    if (elements > 4) names += " and " + std::to_string(elements - 4) + " more";
    if (triangles > 0)
      res.warnings.push_back("the CAD's faces of " + names + " (" + std::to_string(triangles) +
                             " triangles) were wound inside out or against their neighbours: turned outward");
  }

  // paper 4.1.1: radius outlier removal with parameters derived from the resolution.
  report("filter", 0.0);
  std::vector<std::uint32_t> kept;
  {
    const KdTree tree = sort_for_search(scan);  // a tree over points in its leaf order copies none (issue 8)
    RadiusOutlierResult ror = remove_radius_outliers(tree, params.outliers);
    res.outlier_radius_mm = ror.radius_mm;
    res.outlier_min_neighbors = ror.min_neighbors;
    kept = std::move(ror.kept);
  }  // the scan's tree is freed before the copy
  Cloud filtered = select(scan, kept);
  scan = Cloud{};
  release_memory(kept);
  return_free_heap_to_os();  // the scan's tree: peak memory is set by the phases, not by what they left
  res.filtered_points = filtered.size();
  if (filtered.size() < 10) throw ProcessingError("fewer than 10 scan points are left after outlier removal");
  report("filter", 1.0);
  clock.lap("filter");

  // A scan written in another camera convention than the contract's (z forward, y down): looking along -z with y up
  // (OpenGL's, Blender's) or along +x with z up (a body frame, as ROS's camera_link; register/sensor_origin.hpp) is
  // turned into it for the inspection, its initial pose with it; report.json's transform maps the scan as given.
  // (Left as it was, a -z scan read as no depth image from its origin: 100 % of its points "behind" on their ray.)
  std::optional<Pose> initial = initial_scan_to_cad;
  {
    const ScanConvention convention = scan_convention(filtered.points);
    if (!convention.turn.isIdentity()) {
      res.scan_to_sensor.linear() = convention.turn;
      const Eigen::Matrix3f turn = convention.turn.cast<float>();
      for (Eigen::Vector3f& p : filtered.points) p = turn * p;
      for (Eigen::Vector3f& n : filtered.normals) n = turn * n;
      if (initial) *initial = *initial * res.scan_to_sensor.inverse();
      res.warnings.push_back(std::string("the scan looks along ") + convention.looks_along + " (" + convention.frame +
                             "): turned for the inspection, which takes z forward and y down; the reported transform "
                             "maps the scan as given");
    }
  }

  // Everything along the sensor's rays (veils, free space, back faces, the tubes' rays, hidden interference) takes
  // the sensor at the scan's origin (CONTRACT: scans in the sensor's frame). A scan saved in another frame (a
  // robot's, the CAD's) is not a depth image from there (register/sensor_origin.hpp): measured and reported, not
  // corrected (the occlusions place its sensor too roughly to stand in for it).
  res.sensor_origin_occluded_fraction = occluded_from_origin(filtered.points);
  res.sensor_at_scan_origin = res.sensor_origin_occluded_fraction <= kNotSensorFrameFraction;
  if (!res.sensor_at_scan_origin)
    res.warnings.push_back("the scan is not a depth image seen from its origin (" +
                           std::to_string(std::lround(100.0 * res.sensor_origin_occluded_fraction)) +
                           " % of its points lie behind others on their ray): it is not in its sensor's frame, which "
                           "the inspection assumes; expect a wrong registration or verdict");
  clock.lap("sensor");

  // paper 4.1.2: registration on the rigid elements (cables move).
  report("register", 0.0);
  ScanToCadResult reg;
  std::shared_ptr<const SurfaceIndex> rigid_index;  // the rigid triangles, from the target when it indexed them
  if (params.register_scan || !initial) {
    const CadTarget target = build_cad_target(scene, plan, params.target);
    reg = register_scan_to_cad(filtered, target, initial, params.registration,
                               [&](std::string_view, double f) { report("register", f); });
    rigid_index = target.surface;
  } else {
    reg.registration.source_to_target = *initial;
    reg.registration.converged = true;
    reg.registration.fitness = 1.0;
    reg.valid = true;
  }
  if (!reg.valid)
    throw ProcessingError("registration to the CAD failed (fitness " + std::to_string(reg.registration.fitness) +
                          ", rmse " + std::to_string(reg.registration.rmse_mm) + " mm, CAD faces in front of the scan " +
                          std::to_string(std::lround(100.0 * reg.free_space.fraction())) + " %)");
  res.scan_to_cad = reg.registration.source_to_target;
  res.registration_rmse_mm = reg.registration.rmse_mm;
  res.registration_fitness = reg.registration.fitness;
  res.registration_converged = reg.registration.converged;
  res.registration_global = reg.used_global;
  if (reg.free_space.seen > 0) res.registration_in_front_fraction = reg.free_space.fraction();
  if (!background_explains_fitness(reg.box_fitness, reg.free_space.fraction(), params.registration) &&
      (reg.registration.fitness < params.doubtful_fitness ||
       (reg.registration.fitness < params.registration.trusted_fitness &&
        reg.free_space.fraction() > params.registration.trusted_in_front_fraction))) {
    char text[256];
    std::snprintf(text, sizeof text,
                  "the registration is doubtful (fitness %.2f, %ld %% of the CAD's faces toward the sensor lie in front "
                  "of what it measured): the pose may be wrong, or parts of the CAD are missing from the assembly",
                  reg.registration.fitness, std::lround(100.0 * reg.free_space.fraction()));
    res.warnings.emplace_back(text);
  }
  res.sensor_position = res.scan_to_cad.translation();
  res.optical_axis = res.scan_to_cad.linear().col(2).normalized();
  report("register", 1.0);
  return_free_heap_to_os();  // the CAD target and its views
  clock.lap("register");

  // Everything from here on is in CAD coordinates.
  res.cloud = std::move(filtered);
  {
    const Eigen::Matrix3f rot = res.scan_to_cad.linear().cast<float>();
    const Eigen::Vector3f tr = res.scan_to_cad.translation().cast<float>();
    for (auto& p : res.cloud.points) p = rot * p + tr;
    for (auto& n : res.cloud.normals) n = rot * n;
  }
  // In the tree's leaf order, the tree makes no copy of the points (issue 8: peak memory).
  const KdTree tree = sort_for_search(res.cloud);
  const Cloud& cloud = res.cloud;
  res.resolution_mm = spatial_resolution(tree, 200000).median_mm;
  if (!(res.resolution_mm > 0)) res.resolution_mm = 0.5;
  if (params.min_noise_inflation > 0.0)
    res.noise = estimate_noise_correlation(tree, res.resolution_mm, params.noise_correlation);
  if (res.sensor_at_scan_origin) res.pixel_pitch_rad = angular_pixel_pitch_rad(tree, res.sensor_position, res.resolution_mm);

  // Which elements are cables (flexible) and which are rigid (everything the plan does not call a cable).
  std::vector<bool> is_cable(scene.elements.size(), false);
  for (const PlanElement& e : plan.elements)
    if (e.kind == ElementKind::Cable) {
      const int idx = scene.find(e.name);
      if (idx >= 0) is_cable[idx] = true;
    }
  std::vector<int> rigid_elements;
  for (std::size_t i = 0; i < scene.elements.size(); ++i)
    if (!is_cable[i]) rigid_elements.push_back(int(i));
  // The registration's index when it built one (the same elements: everything the plan does not call a cable).
  if (!rigid_index) rigid_index = std::make_shared<const SurfaceIndex>(scene, rigid_elements);
  const SurfaceIndex& rigid_surfaces = *rigid_index;

  // Points on a rigid CAD surface are never cable points (paper 4.2.1: the trace must not climb onto a
  // bracket or run along a plate).
  std::vector<std::int32_t> rigid_label(cloud.size(), -1);
  parallel_blocks(cloud.size(), 2048, [&](std::size_t b, std::size_t e) {
    // The cloud is in leaf order: a run of consecutive points is a small patch, and the surface index is walked
    // once per run.
    rigid_surfaces.closest_element_each(b, e, params.rigid_surface_mm,
                                        [&](std::size_t i) { return cloud.points[i].cast<double>(); },
                                        [&](std::size_t i, std::int32_t element) { rigid_label[i] = element; });
  });
  std::vector<std::uint8_t> usable(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) usable[i] = rigid_label[i] < 0 ? 1 : 0;
  std::vector<std::size_t> points_on_element(scene.elements.size(), 0);  // the rigid elements' point counts
  for (std::int32_t l : rigid_label)
    if (l >= 0) ++points_on_element[l];
  release_memory(rigid_label);
  clock.lap("prepare");

  // paper 4.2: every cable of the plan, traced from its registered CAD samples.
  std::vector<const PlanElement*> cable_plans;
  for (const PlanElement& e : plan.elements)
    if (e.kind == ElementKind::Cable) cable_plans.push_back(&e);
  std::vector<MeasuredCable> measured(cable_plans.size());
  res.cables.resize(cable_plans.size());
  // One BVH of the whole scene: which CAD samples the sensor sees (the trace's starts), and later what hides a point
  // from it (interference).
  res.scene_caster = std::make_shared<const Raycaster>(scene);
  const Raycaster& caster = *res.scene_caster;
  // Each cable's registered CAD samples, and which of them the sensor sees (the CAD seen from the sensor: nothing,
  // the cable itself included, in front). The seen ones seed first: around a sample on the cable's underside or
  // flank the fullest sphere lies in the mixed pixels hanging below its silhouette or where a touching neighbour
  // meets it, and a start there fails (every start of a cable lying beside another failed so, and the cable was not
  // found).
  struct CadSeeds {
    std::vector<Eigen::Vector3d> points;
    std::vector<std::uint8_t> seen;
    std::vector<std::uint8_t> in_attached;  // inside the box of a rigid element the cable is attached to
  };
  // A cable's attached elements (CONTRACT "attached"), rigid and cables apart.
  struct Attached {
    std::vector<int> rigid, cables;
  };
  const auto attached_of = [&](std::size_t c) {
    Attached out;
    for (const std::string& a : cable_plans[c]->attached) {
      const int idx = scene.find(a);
      if (idx >= 0) (is_cable[idx] ? out.cables : out.rigid).push_back(idx);
    }
    return out;
  };
  const auto cad_spacing_mm = [&](std::size_t c) {
    return params.cable_sample_spacing_mm > 0 ? params.cable_sample_spacing_mm
                                              : std::max(0.5, 0.25 * cable_plans[c]->diameter_mm);
  };
  // A CAD cable sample is covered by a run within this of its chain; a cable displaced from its CAD by more than its
  // radius is looked for as far.
  const auto cover_mm = [&](std::size_t c) {
    return std::max(params.covered_radii * 0.5 * cable_plans[c]->diameter_mm, params.covered_min_mm);
  };
  const auto cad_seeds = [&](std::size_t c) {
    CadSeeds out;
    MeshSamplingParams sp;
    sp.spacing_mm = cad_spacing_mm(c);
    sp.elements = {scene.find(cable_plans[c]->name)};
    sp.seed = 1 + c;
    sp.max_points = 200000;
    const MeshSamples samples = sample_mesh(scene, sp);
    out.points.reserve(samples.cloud.size());
    for (const auto& p : samples.cloud.points) out.points.push_back(p.cast<double>());
    std::vector<Ray> rays(out.points.size());
    for (std::size_t i = 0; i < out.points.size(); ++i) {
      const Eigen::Vector3d d = out.points[i] - res.sensor_position;
      rays[i].origin = res.sensor_position.cast<float>();
      rays[i].direction = d.normalized().cast<float>();
      rays[i].tmax_mm = float(d.norm() + 1.0);
    }
    std::vector<Hit> hits;
    caster.cast(rays, hits);
    out.seen.resize(out.points.size());
    for (std::size_t i = 0; i < out.points.size(); ++i)
      out.seen[i] = hits[i].hit() && hits[i].distance_mm >= rays[i].tmax_mm - 1.0f - kSeenToleranceMm;
    const std::vector<int> rigid = attached_of(c).rigid;
    out.in_attached.resize(out.points.size());
    for (std::size_t i = 0; i < out.points.size(); ++i)
      out.in_attached[i] = std::any_of(rigid.begin(), rigid.end(),
                                       [&](int e) { return inside_box(out.points[i], scene.elements[e], 0.0); });
    return out;
  };
  std::vector<CadSeeds> seeds_of(cable_plans.size());
  // A cable's runs, traced from its CAD samples on the points `base` allows.
  const auto trace_runs = [&](std::size_t c, const std::vector<std::uint8_t>& base) {
    std::vector<TubeTrace> runs;
    const PlanElement& pe = *cable_plans[c];
    const double radius = 0.5 * pe.diameter_mm;
    const std::vector<Eigen::Vector3d>& cad_points = seeds_of[c].points;
    const std::vector<std::uint8_t>& seen = seeds_of[c].seen;
    // Attached elements end the run (CONTRACT "attached").
    const Attached attached = attached_of(c);
    const std::vector<int>& attached_rigid = attached.rigid;
    const std::vector<int>& attached_cable = attached.cables;
    const SurfaceIndex attached_rigid_index(scene, attached_rigid);
    const SurfaceIndex attached_cable_index(scene, attached_cable);
    TubeParams tp;
    tp.radius_mm = radius;
    tp.max_seed_radius_ratio = params.max_seed_radius_ratio;
    tp.thin_max_px = params.thin_cable_max_px;
    const double cover = cover_mm(c);
    tp.seed_search_mm = cover;
    tp.resolution_mm = res.resolution_mm;
    tp.has_sensor = true;
    tp.sensor_position = res.sensor_position;
    if (!attached_rigid.empty() || !attached_cable.empty()) {
      const double box_margin = params.attach_box_margin_radii * radius;
      const double near_surface = radius + std::max(1.0, 0.2 * radius);
      tp.stop_at = [&, box_margin, near_surface, radius](const Eigen::Vector3d& p) {
        for (int e : attached_rigid)
          if (inside_box(p, scene.elements[e], box_margin)) {
            const SurfacePoint s = attached_rigid_index.closest(p, near_surface);
            if (s.found()) return true;
          }
        if (!attached_cable_index.empty() && attached_cable_index.closest(p, 0.5 * radius).found()) return true;
        return false;
      };
    }
    // Runs: trace, mark the run's points unusable and its CAD samples covered, trace again from the rest.
    std::vector<std::uint8_t> run_usable = base;
    tp.usable = &run_usable;
    std::vector<std::uint8_t> covered = seeds_of[c].in_attached;
    const std::size_t min_left = std::max<std::size_t>(20, cad_points.size() * 3 / 100);
    for (int run = 0; run < params.max_runs; ++run) {
      std::vector<Eigen::Vector3d> seeds, seen_seeds;
      for (std::size_t i = 0; i < cad_points.size(); ++i)
        if (!covered[i]) {
          seeds.push_back(cad_points[i]);
          if (seen[i]) seen_seeds.push_back(cad_points[i]);
        }
      if (seeds.size() < min_left) break;
      if (seen_seeds.size() >= min_left) seeds.swap(seen_seeds);
      TubeTrace t = trace_cable(cloud, tree, seeds, radius, tp);
      const bool ok = t.found && !t.segments.empty() && t.length_mm >= params.min_found_length_diameters * pe.diameter_mm;
      if (!ok) break;  // nothing more to find
      // (see InspectParams::min_run_support)
      const bool supported = run_support(t, res.sensor_position, res.resolution_mm) >= params.min_run_support;
      // (see InspectParams::max_seed_radius_ratio)
      const double ratio = std::max(1.0, params.max_seed_radius_ratio);
      const bool own_radius = t.radius_mm * ratio >= radius && t.radius_mm <= ratio * radius;
      // A kept run's CAD samples are covered, and the next run starts elsewhere. A dropped run (on stray points, or of
      // another radius: a neighbour) tells nothing of where this cable is: its points are left out of the next
      // traces, its CAD samples stay to seed them (covered, they hid the cable displaced beside the neighbour the run
      // took: fresh campaign `--seed 2468 --campaign 40 --cables 3 --mismatch-patches 150 --outliers 0.45 --noise-mm
      // 0.25`, scene_027, 204 mm of a 4.4 mm cable untraced and its contact with a bracket missed). Bounded by
      // max_runs.
      const bool kept = supported && own_radius;
      if (kept) {
        std::vector<Cylinder> chain;
        for (const SubCable& s : t.segments) chain.push_back(s.cylinder);
        std::size_t newly = 0;
        for (std::size_t i = 0; i < cad_points.size(); ++i)
          if (!covered[i] && distance_to_chain(chain, cad_points[i]).distance_mm <= cover) {
            covered[i] = 1;
            ++newly;
          }
        if (newly == 0) break;  // nothing more to find (bounded either way)
      }
      for (std::uint32_t i : t.points) run_usable[i] = 0;
      if (kept) runs.push_back(std::move(t));
    }
    return runs;
  };
  // The first traces are most of the stage; touching cables traced again are the rest.
  each_cable(cable_plans.size(), "trace", 0.9, [&](std::size_t c) {
    const PlanElement& pe = *cable_plans[c];
    CableInspection& ci = res.cables[c];
    ci.name = pe.name;
    ci.element = scene.find(pe.name);
    ci.nominal_diameter_mm = pe.diameter_mm;
    ci.allowed_bend_radius_mm = pe.allowed_bend_radius_mm();
    ci.bend_reference = pe.bend_reference;
    ci.clearance_mm = pe.clearance_mm;
    seeds_of[c] = cad_seeds(c);
    ci.runs = trace_runs(c, usable);
  });
  // Touching cables (a bundle tied together, one cable lying on another): traced alone, a cable takes in the
  // sliver of its neighbour's surface beside the contact, which lies within its own surface band; its fitted
  // axis leans towards the neighbour and its radius grows (two 5.6 mm cables touching: +7 % each, a 4 mm one
  // beside them traced over 15 % of its length). So a cable whose chain comes within both radii + untangle_margin
  // of another's is traced again without the points that lie nearer the other's fitted surface than its own
  // (both judged on the first traces, so the order of the cables does not matter).
  if (params.untangle_touching && cable_plans.size() > 1) {
    // A first run on another cable's run (most points shared), whose place that cable's CAD claims
    // (run_conflicts.hpp), is not its cable's surface: left out of the chains judged here, and the cable is traced
    // again without the other run's points. A cable moved off its CAD onto a neighbour's place has its CAD samples
    // on the neighbour (J60 scene_057: cable_A 10-15 mm from its CAD, cable_C along it): its first trace takes the
    // neighbour, and untangled by the nearer surfaces alone the two split the neighbour's points between them (the
    // neighbour lost half its points, A walked along the rest), while A's own points beside it went untraced.
    std::vector<RunOnOtherCable> on_other;
    if (params.retrace_runs_on_others) on_other = runs_on_other_cables(res.cables, scene, cloud.points);
    std::vector<std::vector<std::uint8_t>> lost(cable_plans.size());
    for (std::size_t c = 0; c < cable_plans.size(); ++c) lost[c].assign(res.cables[c].runs.size(), 0);
    for (const RunOnOtherCable& o : on_other) lost[o.cable][o.run] = 1;
    struct First {
      std::vector<Cylinder> chain;
      double radius_mm = 0;
    };
    std::vector<First> first(cable_plans.size());
    for (std::size_t c = 0; c < cable_plans.size(); ++c) {
      std::vector<double> radii;
      for (std::size_t k = 0; k < res.cables[c].runs.size(); ++k) {
        if (lost[c][k]) continue;
        for (const SubCable& s : res.cables[c].runs[k].segments) {
          first[c].chain.push_back(s.cylinder);
          if (!s.bridged) radii.push_back(s.cylinder.radius_mm);
        }
      }
      if (!radii.empty()) first[c].radius_mm = median_in_place(radii);
    }
    std::vector<std::optional<std::vector<TubeTrace>>> again(cable_plans.size());  // traced again, all at once
    parallel_for_each_index(cable_plans.size(), [&](std::size_t c) {
      std::vector<std::uint8_t> mask;  // `usable` less the points dropped, made on the first drop
      std::size_t dropped = 0;
      const auto drop = [&](std::uint32_t i) {
        if (mask.empty()) mask = usable;
        if (!mask[i]) return;
        mask[i] = 0;
        ++dropped;
      };
      for (const RunOnOtherCable& o : on_other)
        if (o.cable == c)
          for (std::uint32_t i : res.cables[o.other_cable].runs[o.other_run].points) drop(i);
      // No start found at all (InspectParams::retrace_unfound): beside a touching neighbour every start sphere on the
      // CAD held the neighbour's surface too; without the other cables' runs the cable's own surface is left.
      if (params.retrace_unfound && res.cables[c].runs.empty())
        for (std::size_t o = 0; o < cable_plans.size(); ++o)
          for (std::size_t k = 0; o != c && k < res.cables[o].runs.size(); ++k)
            if (!lost[o][k])
              for (std::uint32_t i : res.cables[o].runs[k].points) drop(i);
      if (!first[c].chain.empty())
        for (std::size_t o = 0; o < cable_plans.size(); ++o) {
          if (o == c || first[o].chain.empty()) continue;
          const double reach = first[c].radius_mm + first[o].radius_mm + params.untangle_margin_mm;
          if (chain_distance(first[c].chain, first[o].chain) > reach) continue;
          if (mask.empty()) mask = usable;
          for (std::size_t k = 0; k < res.cables[o].runs.size(); ++k) {
            if (lost[o][k]) continue;
            for (std::uint32_t i : res.cables[o].runs[k].points) {
              if (!mask[i]) continue;
              const Eigen::Vector3d p = cloud.points[i].cast<double>();
              const double own = std::abs(distance_to_chain(first[c].chain, p).distance_mm - first[c].radius_mm);
              const double other = std::abs(distance_to_chain(first[o].chain, p).distance_mm - first[o].radius_mm);
              if (other < own) drop(i);
            }
          }
        }
      if (dropped > 0) again[c] = trace_runs(c, mask);
    }, 1);
    for (std::size_t c = 0; c < cable_plans.size(); ++c)
      if (again[c] && !again[c]->empty()) res.cables[c].runs = std::move(*again[c]);
  }

  // Two cables' runs on the same points: the place goes to the cable whose CAD is nearer (run_conflicts.hpp).
  drop_runs_on_other_cables(res.cables, scene, cloud.points);

  for (std::size_t c = 0; c < cable_plans.size(); ++c) {
    CableInspection& ci = res.cables[c];
    ci.found = !ci.runs.empty();
    if (ci.found) {
      TubeTrace& m = ci.trace;
      m = ci.runs.front();
      double weighted = 0;
      std::size_t weight = 0;
      m.length_mm = 0;
      m.segments.clear();
      m.gaps.clear();
      m.points.clear();
      for (const TubeTrace& t : ci.runs) {
        m.segments.insert(m.segments.end(), t.segments.begin(), t.segments.end());
        m.gaps.insert(m.gaps.end(), t.gaps.begin(), t.gaps.end());
        m.points.insert(m.points.end(), t.points.begin(), t.points.end());
        m.length_mm += t.length_mm;
        weighted += t.radius_mm * double(std::max<std::size_t>(1, t.points.size()));
        weight += std::max<std::size_t>(1, t.points.size());
      }
      m.radius_mm = weighted / double(weight);
      std::sort(m.points.begin(), m.points.end());
      m.points.erase(std::unique(m.points.begin(), m.points.end()), m.points.end());
    }
    MeasuredCable& m = measured[c];
    m.name = cable_plans[c]->name;
    m.element = ci.element;
    m.found = ci.found;
    if (ci.found) {
      m.radius_mm = ci.trace.radius_mm;
      for (const SubCable& s : ci.trace.segments) m.chain.push_back(s.cylinder);
      m.points = ci.trace.points;
    }
  }
  // How much of each found cable's CAD its runs cover (InspectParams::min_traced_fraction).
  parallel_for_each_index(cable_plans.size(), [&](std::size_t c) {
    if (!measured[c].found) return;
    const CadSeeds& seeds = seeds_of[c];
    std::size_t total = 0, traced = 0;
    for (std::size_t i = 0; i < seeds.points.size(); ++i) {
      if (seeds.in_attached[i]) continue;
      ++total;
      if (distance_to_chain(measured[c].chain, seeds.points[i]).distance_mm <= cover_mm(c)) ++traced;
    }
    res.cables[c].cad_traced_fraction = total > 0 ? double(traced) / double(total) : 1.0;
  }, 1);
  report("trace", 1.0);
  clock.lap("trace");

  // paper 4.3.1: bend radius, every cable at once; the fits count the scan's noise correlation where it matters
  // (InspectParams::min_noise_inflation).
  FilletRefineParams fillet_params = params.fillet;
  if (params.min_noise_inflation > 0.0 && res.noise.inflation >= params.min_noise_inflation) {
    fillet_params.fit.noise = &res.noise;
    fillet_params.smooth_fit.noise = &res.noise;
  }
  parallel_for_each_index(res.cables.size(), [&](std::size_t c) {
    CableInspection& ci = res.cables[c];
    if (!ci.found) return;
    ci.diameter_mm = 2.0 * ci.trace.radius_mm;
    ci.length_mm = ci.trace.length_mm;
    // The smallest radius over the runs; the paper's figure from the same run.
    std::size_t best_run = 0;
    FilletScan fs;
    fs.cloud = &cloud;
    fs.tree = &tree;
    fs.usable = &usable;
    fs.has_sensor = res.sensor_at_scan_origin;
    fs.sensor_position = res.sensor_position;
    // Clumps standing off a run's surface by a step (a sensor's matching errors, surface_clumps.hpp), among the scan
    // points in and around its tube, are left out of the bend fits: out of each run's surface points, and out of the
    // scan points the fits gather again.
    std::vector<std::uint8_t> clump_free;  // `usable` without them (empty: none found)
    if (res.sensor_at_scan_origin && params.surface_clumps.enabled) {
      std::vector<Neighbor> nbs;
      for (const TubeTrace& run : ci.runs) {
        // The usable points within the tube (a patch moved into it lies off the trace's band) and a margin around it
        // (the band the fits gather again in); `near` in the tree's visiting order, each once.
        const double reach = run.radius_mm + std::max(params.surface_clumps.margin_mm,
                                                      params.surface_clumps.margin_radii * run.radius_mm);
        std::vector<std::uint32_t> near;
        for (const Eigen::Vector3d& c : run.centerline) {
          tree.radius_unsorted(c.cast<float>(), float(reach), nbs);
          for (const Neighbor& nb : nbs)
            if (usable[nb.index]) near.push_back(nb.index);
        }
        std::sort(near.begin(), near.end());
        near.erase(std::unique(near.begin(), near.end()), near.end());
        std::vector<Eigen::Vector3d> surface;
        surface.reserve(near.size());
        for (std::uint32_t i : near) surface.push_back(cloud.points[i].cast<double>());
        const SurfaceClumps sc = surface_step_clumps(surface, run.centerline, run.radius_mm, res.sensor_position,
                                                     res.resolution_mm, params.surface_clumps);
        if (sc.points.empty()) continue;
        if (clump_free.empty()) clump_free = usable;
        for (std::uint32_t j : sc.points) clump_free[near[j]] = 0;
      }
      if (!clump_free.empty()) fs.usable = &clump_free;
    }
    const auto kept = [&](std::uint32_t i) { return clump_free.empty() || clump_free[i]; };
    for (std::size_t k = 0; k < ci.runs.size(); ++k) {
      BendRadiusResult b = measure_bend_radius(ci.runs[k].centerline, ci.nominal_diameter_mm, params.bend);
      // Tight bends again, on the run's surface points (a short arc is a corner to any centreline window).
      std::vector<Eigen::Vector3d> surface;
      surface.reserve(ci.runs[k].points.size());
      for (std::uint32_t i : ci.runs[k].points)
        if (kept(i)) surface.push_back(cloud.points[i].cast<double>());
      refine_bends_with_fillets(b, ci.runs[k].centerline, surface, ci.runs[k].radius_mm, ci.nominal_diameter_mm,
                                fillet_params, fs);
      const bool better = k == 0 || (b.min_radius_mm && (!ci.bend.min_radius_mm || *b.min_radius_mm < *ci.bend.min_radius_mm));
      if (better) {
        ci.bend = std::move(b);
        best_run = k;
      }
    }
    ci.forks = run_forks(ci.runs, ci.nominal_diameter_mm, params.joins);
    // A bend hidden between two runs (an occluder across it split the cable there): measured across the gap by the
    // fillet on both sides' surface points; the straight line drawn over the gap is no measurement, so only a
    // fillet reading at the gap counts.
    for (const RunJoin& j : join_runs_across_gaps(ci.runs, cloud.points, ci.nominal_diameter_mm, params.joins)) {
      BendRadiusResult b = measure_bend_radius(j.centerline, ci.nominal_diameter_mm, params.bend);
      // without the occluder's mixed pixels at the gap's ends
      FilletScan join_scan = fs;
      std::vector<std::uint8_t> join_usable;
      if (res.sensor_at_scan_origin && params.joins.drop_edge_points) {
        const std::vector<std::uint32_t> under = points_under_something(
            j, cloud.points, tree, &usable, res.sensor_position, ci.nominal_diameter_mm, params.joins);
        if (!under.empty()) {
          join_usable = *fs.usable;
          for (std::uint32_t i : under) join_usable[i] = 0;
          join_scan.usable = &join_usable;
        }
      }
      std::vector<Eigen::Vector3d> surface;
      surface.reserve(j.points.size());
      for (std::uint32_t i : j.points)
        if (join_usable.empty() ? kept(i) : join_usable[i]) surface.push_back(cloud.points[i].cast<double>());
      FilletRefineParams across = fillet_params;
      across.leg_drift_inside = params.joins.fillet_leg_drift_inside;
      refine_bends_with_fillets(b, j.centerline, surface, j.radius_mm, ci.nominal_diameter_mm, across, join_scan);
      if (!b.min_radius_mm || !b.location || std::string_view(b.min_radius_model) != "fillet") continue;
      const double near = std::max(params.joins.near_gap_diameters * ci.nominal_diameter_mm, params.joins.near_gap_min_mm);
      if (distance_to_segment(Cylinder{j.gap_start, j.gap_end, j.radius_mm}, *b.location) > near) continue;
      if (!ci.bend.min_radius_mm || *b.min_radius_mm < *ci.bend.min_radius_mm) {
        ci.bend = std::move(b);
        best_run = j.first;
      }
    }
    ci.min_bend_radius_mm = ci.bend.min_radius_mm;
    ci.min_bend_location = ci.bend.location;
    if (ci.min_bend_radius_mm) ci.min_bend_radius_inner_mm = *ci.min_bend_radius_mm - 0.5 * ci.diameter_mm;
    std::vector<Cylinder> run_chain;
    for (const SubCable& s : ci.runs[best_run].segments) run_chain.push_back(s.cylinder);
    ci.paper_bend = paper_bend_radius(run_chain, res.optical_axis, ci.nominal_diameter_mm, params.paper_bend);
  }, 1);
  // The bend verdicts, in cable order (for the warnings): the reading against the limit; a bound over it passes only
  // when its fit + bound_verdict_se standard errors reaches the limit too (InspectParams::bound_verdict_se).
  for (CableInspection& ci : res.cables) {
    if (!ci.found) continue;
    ci.bend_ok = true;
    if (!(ci.allowed_bend_radius_mm > 0) || !ci.min_bend_radius_mm) continue;
    const bool inner = ci.bend_reference == BendReference::Inner;
    const double measured_mm = inner ? *ci.min_bend_radius_inner_mm : *ci.min_bend_radius_mm;
    ci.bend_ok = measured_mm >= ci.allowed_bend_radius_mm;
    if (!*ci.bend_ok || !ci.bend.min_radius_is_bound) continue;
    const double fit_mm = ci.bend.min_radius_fit_mm - (inner ? 0.5 * ci.diameter_mm : 0.0);
    if (fit_mm + params.bound_verdict_se * ci.bend.min_radius_se_mm >= ci.allowed_bend_radius_mm) continue;
    ci.bend_ok = false;
    char text[400];
    std::snprintf(text, sizeof text,
                  "%s: a kink too short for its radius to be measured: its %s radius is at most %.2f mm, but its "
                  "best fit, %.2f +- %.2f mm, lies more than %.1f standard errors under the allowed %.2f mm: the bend "
                  "fails",
                  ci.name.c_str(), inner ? "inner" : "centreline", measured_mm, fit_mm, ci.bend.min_radius_se_mm,
                  params.bound_verdict_se, ci.allowed_bend_radius_mm);
    res.warnings.emplace_back(text);
  }
  clock.lap("bend");

  // paper 4.3.2: interference, cable by cable.
  std::vector<int> cable_elements;
  for (std::size_t i = 0; i < scene.elements.size(); ++i)
    if (is_cable[i]) cable_elements.push_back(int(i));
  const SurfaceIndex cable_cad(scene, cable_elements);
  const Eigen::Vector3d sensor = res.sensor_position;
  const double hidden_margin = params.hidden_margin_mm;
  // The scene's BVH for every cable: a hit on the cable being checked is passed through.
  return_free_heap_to_os();
  each_cable(res.cables.size(), "interference", 1.0, [&](std::size_t c) {
    CableInspection& ci = res.cables[c];
    if (!ci.found) return;
    std::vector<int> ignore = {ci.element};
    for (const std::string& a : cable_plans[c]->attached) ignore.push_back(scene.find(a));
    InterferenceParams ip = params.interference;
    ip.clearance_mm = ci.clearance_mm;
    ip.resolution_mm = res.resolution_mm;
    ip.pixel_pitch_rad = res.pixel_pitch_rad;
    ip.has_sensor = true;
    ip.sensor_position = res.sensor_position;
    InterferenceContext context;
    context.cable_cad = &cable_cad;
    context.own_cad_samples = &seeds_of[c].points;
    context.own_cad_spacing_mm = cad_spacing_mm(c);
    context.own_cad_traced_within_mm = cover_mm(c);
    context.untraced_parts = &ci.untraced_parts;
    // Every CAD element but this cable may hide a point from the sensor (then it is a mixed pixel).
    const auto own = static_cast<std::uint32_t>(ci.element);
    context.hidden_by_rigid = [&caster, sensor, hidden_margin, own](const Eigen::Vector3d& p) {
      const Eigen::Vector3d d = p - sensor;
      const double len = d.norm();
      if (!(len > hidden_margin)) return false;
      Ray ray;
      ray.origin = sensor.cast<float>();
      ray.direction = (d / len).cast<float>();
      ray.tmax_mm = float(len - hidden_margin);
      for (int crossing = 0; crossing < 16; ++crossing) {
        const Hit h = caster.cast(ray);
        if (!h.hit()) return false;
        if (h.element != own) return true;
        const float step = h.distance_mm + 1e-3f;  // through this cable's surface, on along the same line
        ray.origin += ray.direction * step;
        ray.tmax_mm -= step;
        if (!(ray.tmax_mm > 0)) return false;
      }
      return true;
    };
    ci.interferences = find_interferences(cloud, tree, scene, rigid_surfaces, measured, c, ignore, ip, context);
    ci.clearance_ok = ci.interferences.empty();
  });
  const auto where = [](const Eigen::Vector3d& p) {
    char text[96];
    std::snprintf(text, sizeof text, "(%.1f, %.1f, %.1f)", p.x(), p.y(), p.z());
    return std::string(text);
  };
  for (const CableInspection& ci : res.cables) {
    if (ci.found && ci.cad_traced_fraction < params.min_traced_fraction)
      res.warnings.push_back(ci.name + ": traced along " + std::to_string(std::lround(100.0 * ci.cad_traced_fraction)) +
                             " % of its CAD only (hidden, or displaced from its CAD?): the rest was not inspected");
    for (const Eigen::Vector3d& p : ci.forks)
      res.warnings.push_back(ci.name + ": forks at " + where(p) +
                             " (a branch traced as a run of its own: no bend is measured across the fork)");
    for (const Eigen::Vector3d& p : ci.untraced_parts)
      res.warnings.push_back(ci.name + ": part of its CAD seen at " + where(p) +
                             " was not traced (a branch of another diameter than the plan's?); it is not inspected");
  }
  clock.lap("interference");
  return_free_heap_to_os();  // before the caller writes reports and pictures

  if (params.list_rigid) {
    for (const PlanElement& e : plan.elements) {
      if (e.kind != ElementKind::Rigid) continue;
      RigidInspection r;
      r.name = e.name;
      r.element = scene.find(e.name);
      if (r.element >= 0) r.points = points_on_element[r.element];
      res.rigid.push_back(r);
    }
  }

  res.pass = true;
  for (const CableInspection& ci : res.cables)
    if (!ci.found || ci.bend_ok == false || ci.clearance_ok == false) res.pass = false;
  return res;
}

}  // namespace ewis
