#pragma once
// Interference (clearance) detection, paper 4.3.2: S = the cable's points, P = every other (filtered) point.
// Points of P closer than clearance_mm to the cable's FITTED surface (distance to the chain's axis minus its
// radius) are labelled with what they lie on, clustered (Euclidean clustering over the k-d tree) per label,
// small clusters are dropped, and each kept one is reported with the true surface-to-surface gap:
//  - label: another measured cable when the point is one of its points or within label_tolerance_mm of its
//    fitted surface; else the rigid CAD element whose registered surface is within label_tolerance_mm
//    (the nearer one wins); else nothing: a foreign object (`with` null); only foreign points are clustered:
//    rigid elements and other cables are checked on their models (below);
//  - a rigid element is an interference when its registered CAD surface comes closer than clearance_mm to
//    the measured chain and the scan shows the element there (support_radius_mm);
//  - foreign clusters that are veils of mixed pixels (see veil_cos_max) are dropped;
//  - the cable's own CAD element and the elements of its `attached` list are never interferences;
//  - P points within own_surface_band_mm of the cable's own fitted surface are its own points that the trace
//    did not claim (mixed pixels on its silhouette), and points whose nearest chain point is past the chain's
//    ends are its untraced continuation (into a connector or clamp): both are ignored; so are mixed pixels on
//    the cable's silhouette rays (see InterferenceParams::has_sensor);
//  - clusters smaller than max(min_cluster_points, min_cluster_area_mm2 / resolution^2) points (about a
//    2 x 2 mm patch at the scan's resolution; with the sensor known counted in pixels, points on one camera ray
//    once) are noise; the clustering links points closer than cluster_tolerance_factor x resolution (at least 1 mm);
//    so are clusters whose whole object (grown over the points on nothing known) covers under min_object_area_mm2;
//  - another measured cable is checked on the fitted models alone: its chain-to-chain gap below clearance_mm
//    is an interference (a cable crossing on top shows the sensor only its far side, so no point of it lies
//    within the clearance); its points near the crossing are the entry's points (none: not reported);
//  - all kept clusters with the same `with` (a named element) are merged into ONE entry (its points, centre
//    and the element's gap); foreign-object clusters stay separate;
//  - min_distance_mm (DESIGN.md "Measurement lessons": the facing flanks are never seen, so point gaps read
//    wide): to another cable, the distance between the two chains' axes minus both radii; to a rigid element,
//    the exact distance from the cable's axis to the element's registered CAD triangles minus the radius;
//    to a foreign object, the least (axis distance minus radius) over the cluster's points. Clamped at 0. An
//    entry whose surface gap is not below clearance_mm is dropped (the points were close, the surfaces not).
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ewis/core/cloud.hpp"
#include "ewis/core/cylinder.hpp"
#include "ewis/scene/surface_index.hpp"
#include "ewis/scene/scene.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis {

// A cable as measured (the traced chain), in the cloud's frame.
struct MeasuredCable {
  std::string name;
  int element = -1;                     // its CAD element in the scene, -1 when absent
  bool found = false;
  double radius_mm = 0.0;               // fitted radius
  std::vector<Cylinder> chain;          // sub-cables, end to end
  std::vector<std::uint32_t> points;    // its scan points (cloud indices), sorted (the set S)
};

struct InterferenceParams {
  double clearance_mm = 0.0;            // the plan's least allowed surface-to-surface gap
  double resolution_mm = 0.5;           // scan point spacing R(PC)
  double cluster_tolerance_factor = 3.0;
  std::size_t min_cluster_points = 10;
  double min_cluster_area_mm2 = 4.0;
  // A foreign cluster is reported only when the whole object it belongs to covers at least
  // max(min_cluster size, min_object_area_mm2 / resolution^2) pixels (points without the sensor): the cluster grown
  // over the cloud's points that lie on nothing known (not on a cable, a rigid surface or the cable's own band), not
  // only its part near the cable. A stereo sensor's mismatch patches (shiny or dark spots: a block of pixels at one
  // wrong depth, up to a few pixels a side) survive radius outlier removal as dense clumps standing alone in space;
  // beside or over a cable they read as small objects (`ewis simulate --seed 4040 --campaign 40 --mismatch-patches
  // 300`: 19 of its 20 clean scenes were false alarms, clumps of 14-36 points). A real object lying on or near the
  // cable shows more of itself than its part within the clearance (the campaigns' smallest foreign objects, spheres
  // of 3 mm radius, grow to 100+ pixels; their parts near the cable held 18-33). 16 mm^2: 4 x 4 mm, 64 pixels at
  // 0.5 mm; smaller compact objects are not told apart from mismatch patches by one shot.
  double min_object_area_mm2 = 16.0;
  // The sensor's angular pixel pitch (filter/pixel_pitch.hpp; 0: unknown). With it and the sensor known, an object's
  // pixels count as (pitch x its range)^2 each against min_object_area_mm2, rather than resolution^2: noise across the
  // rays shortens the resolution (0.44 mm for pixels 0.52 mm apart), which asked a small object to cover 1.4 times
  // the area (bench/small_objects.py: balls under 5 mm were missed).
  double pixel_pitch_rad = 0.0;
  // ... or, smaller (but at least the minimum cluster size), when it is at least min_object_length_mm long as the
  // sensor sees it (the widest spread of its pixels): a wire clipping (safety wire of 0.8 mm: 1-2 pixels wide) lying
  // over a cable is a classic foreign object, and no mismatch patch (a matching window's block, 3 mm across at most
  // here, 4.2 mm corner to corner) is that long. 0: the area alone.
  double min_object_length_mm = 8.0;
  double label_tolerance_mm = 2.5;      // registration + noise: a point this near a surface lies on it
  double own_surface_band_mm = 1.0;
  double surface_step_mm = 0.25;        // sampling step along the axis for the gap to CAD triangles
  // A rigid element closer than the clearance (CAD surface to chain) is reported only when the scan shows it
  // there: at least the minimum cluster size of points on its surface within max(support_radius_mm,
  // 2 r + clearance) of the closest spot.
  double support_radius_mm = 10.0;
  // Mixed pixels (a depth between a cable's silhouette and the background, on the silhouette's rays): with
  // the sensor position known, a point whose camera ray passes a measured cable's fitted surface closer than
  // ray_graze_mm (<= 0: the resolution, about a pixel's footprint) and markedly closer (ray_graze_margin_mm)
  // than the point itself lies from it is such a pixel, or hidden behind the cable: not a surface seen there.
  bool has_sensor = false;
  Eigen::Vector3d sensor_position = Eigen::Vector3d::Zero();  // the cloud's frame
  double ray_graze_mm = 0.0;
  double ray_graze_margin_mm = 0.5;
  // An object lying over the cable on the sensor's side shows only its top: its points read up to its
  // thickness farther than its hidden underside. With the sensor known, points up to occlusion_extra_mm beyond
  // the clearance whose camera ray, continued, hits the cable (they hide it) are candidates too, and a
  // foreign cluster with at least the minimum cluster size of such points is reported even when its seen
  // points are all beyond the clearance (`occluding`; its min_distance_mm is then an upper bound).
  double occlusion_extra_mm = 10.0;
  // ... and, more generally, points up to occlusion_extra_mm beyond the clearance whose camera ray, continued behind
  // them to the cable's far side, passes within the clearance of the cable's surface: the object's unseen body
  // behind what the sensor sees may come that close (a sphere seen from above beside a cable shows its top, and its
  // hidden flank is the part nearest the cable: fresh campaign seed 4040 scene_015, a 13.4 mm sphere 3.3 mm from a
  // cable with a 6 mm clearance, its nearest seen point 7 mm away, was missed; so would be a tall box beside a cable
  // seen from above). Such a cluster is reported when at least the minimum cluster size of its points are these;
  // its min_distance_mm is the seen points' (an upper bound). False: only points whose ray hits the cable.
  bool shadow_within_clearance = true;
  // A point that is on no measured cable and no rigid surface but within cable_cad_tolerance_mm of another
  // cable's registered CAD surface is that cable's (a stretch its trace did not cover, e.g. where it crosses
  // over this one): not a foreign object. Cables stray from their CAD, hence the wider tolerance.
  double cable_cad_tolerance_mm = 6.0;
  // Veils: mixed pixels along a depth edge (between two parallel cables, a cable and the plate behind it) lie
  // on the rays of the edge's pixels, so they form a curtain that contains the viewing rays. A surface the
  // sensor really sees faces it (and one seen at a grazing angle is sampled too sparsely to form a cluster). With
  // the sensor known, a foreign cluster whose points mostly (veil_fraction) have a local normal (PCA over
  // veil_radius_mm, at least 4 x resolution) within acos(veil_cos_max) of perpendicular to their ray is a veil,
  // not an object.
  double veil_cos_max = 0.25;
  double veil_fraction = 0.6;
  double veil_radius_mm = 2.0;
  // ... and whose footprint across the mean viewing ray is at most max(veil_max_width_mm, veil_max_width_res x
  // resolution) wide (a curtain along a depth edge is a pixel or two wide; an object seen obliquely is not),
  // measured on its pixels (points on one camera ray count once) within max(veil_local_radius_mm, 6 x resolution) of
  // each (the median over the cluster: a curtain along an edge that turns a corner or curves is narrow locally, not
  // as a whole).
  double veil_max_width_mm = 1.5;
  double veil_max_width_res = 3.0;
  double veil_local_radius_mm = 3.0;
  // A veil may hold an object: the mixed pixels along a cable's silhouette and the seen cap of a sphere lying against
  // the cable, linked within the cluster tolerance, formed one cluster, mostly veil, and the sphere (7.1 mm, 0.27 mm
  // from a 10.5 mm cable) was missed (fresh campaign `--seed 9191 --campaign 40 --cables 3 --pose-error-deg 5
  // --pose-error-mm 30 --outliers 0.5`, scene_005). The points of a veil whose surface faces the sensor (|cos| of their
  // normal and ray at least veil_facing_cos), but not those on stacked pixels (stack_min_spread_mm), are clustered
  // again, and each part is judged as a cluster of its own (a veil's own points lie along the rays). <= 0: no such
  // second look.
  double veil_facing_cos = 0.5;
  // Pixels (points on one camera ray, see image_footprint in interference.cpp) holding points more than
  // stack_min_spread_mm apart along the ray are stacks of mixed pixels: a sensor measures one depth per pixel, and a
  // simulator that puts several mixed points on an edge pixel's ray makes them. A cluster whose pixels are mostly
  // (veil_fraction) stacks is a veil whatever its shape (fresh campaign seed 6262 scene_050: 119 points on 12 pixels,
  // 9 of them stacks, a blob 2 mm wide over a thin cable beside a 23 mm hose). A real sensor gives no stacks, and a
  // cloud merged from several shots gives them within its noise only.
  double stack_min_spread_mm = 1.0;
  // Depth noise about the surfaces: a sensor's wrong ranges (a mismatched stripe, a lost correspondence), or another
  // simulator's outliers (points moved a few mm), put points in front of and beside the surfaces they belong to, a
  // scatter within a few mm of them which radius outlier removal keeps (the surface is near) and which near a cable
  // reads as small objects all along it (a halo of 40 % of the pixels off by a Gaussian 1.5 mm along the ray: all 15
  // clean scenes of a 30-scene campaign were false alarms, clusters of 14-31 points 1.0-1.1 mm from the cable). A
  // point of a seen surface has neighbours at its range on the rays next to its own (within float_lateral_res x
  // resolution of its ray): the surface goes on there. A point floats when those rays hold fewer than float_min_same
  // points within float_range_tolerance_mm of its range, and fewer than float_min_sides on one side of it (within
  // float_reach_mm along them: a surface's noise, and a surface seen at a grazing angle, put its neighbours on both
  // sides; a wrong range floats in front of the surface it belongs to, or beside it over nothing), and when it does not
  // lie on the surface seen around it either: the plane over the points on the float_rays rays nearest its own (within
  // float_surface_lateral_res x resolution of it, points within float_same_ray_res x resolution across the rays being
  // one ray's) that the most rays hold within float_range_tolerance_mm, held by at least float_min_inliers of them,
  // passes farther than that from it along its ray (filter/ray_neighbours.hpp, seen_surface_at; float_rays 0: not
  // asked). A foreign cluster of which at least float_fraction of the points (up to float_samples of them, evenly
  // strided) float is noise, not an object. With the sensor known only; float_min_same 0: no such test.
  // The surface (forty-second session, docs/inspect.md "Or on the surface the rays around it saw"): another scanner's
  // objects seen at 45-78 deg, pixels lost at that incidence, 0.2 mm of noise across the rays and pixels 0.63 mm apart
  // against a measured resolution of 0.51 mm, had 46-54 % of their points floating by the count alone and were missed;
  // 13-16 % with the surface. The plane alone would not do: where stacks (several ranges on one ray) fill the nearest
  // rays or another surface shows beside an object, its plane is not always the one most rays hold. Measured with both:
  // objects 0-30 % floating (under a halo of 40 % of the pixels off along the ray by a Gaussian 1.5 or 3 mm: 25-30 %),
  // those halos' clusters 71-97 % but for one of 16 points at 44 %; copies added 3 mm beside the surfaces (which no
  // sensor gives) 38-65 %: hence 0.4, not the majority (0.5 before the plane). The tolerance is not scaled by the scan's noise estimate: such noise inflates it (0.44 mm
  // for 0.2 mm of sensor noise). A wire one pixel wide under such noise would float: one shot does not tell it from
  // the noise.
  double float_lateral_res = 1.5;
  double float_range_tolerance_mm = 0.6;
  double float_reach_mm = 5.0;
  std::size_t float_min_same = 2;
  std::size_t float_min_sides = 2;
  double float_surface_lateral_res = 2.5;
  double float_same_ray_res = 0.25;
  std::size_t float_rays = 8;
  std::size_t float_min_inliers = 5;
  std::size_t float_samples = 64;
  double float_fraction = 0.4;
  // Breaks between the cable's runs up to this many diameters are bridged for the point checks
  // (bridge_short_breaks): an object lying over the cable splits its trace but is still near it.
  // ... and at least bridge_break_min_mm: what hides a cable does not scale with it (campaign seed 5151 scene_005:
  // a 14 mm box beside a 4.2 mm cable broke its trace for 25.6 mm, 6.1 diameters, and was missed).
  double bridge_break_diameters = 6.0;
  double bridge_break_min_mm = 40.0;
  // Over a bridge the cable's own surface band is at least this many radii (the course there is guessed).
  double bridge_band_radii = 0.25;
  // A foreign cluster lying mostly over a bridge is the cable's own untraced stretch when a cylinder fitted to it
  // has the cable's radius (within this fraction), holds this fraction of its points as inliers, runs within this
  // angle of the bridge and has its axis within a radius of the bridge's course.
  double own_stretch_radius_tolerance = 0.25;
  double own_stretch_min_inliers = 0.6;
  double own_stretch_max_angle_deg = 25.0;
  // ... or, when the free fit's radius is off (a sliver of the surface: the part beyond the band), a tube of the
  // cable's radius fits it with an RMS within this factor of the free fit's
  double own_stretch_fixed_rms_factor = 1.25;
  // A foreign cluster whose whole object (grown as for min_object_area_mm2, but up to own_part_max_points points) lies
  // mostly (own_part_min_fraction) on the cable's own registered CAD surface, nearer it by own_part_margin_mm than
  // to the measured cable's surface, and reaches (at least the minimum cluster size of its points) the cable's CAD
  // where none of its runs was traced, is a part of the cable the trace did not follow, not a foreign object: a branch
  // of a harness (one element of the CAD) of another diameter than the plan's, which no start of the plan's radius
  // takes (a 5 mm branch off a 7.2 mm trunk read as a foreign object 1.0 mm from it). "On" the CAD: within
  // label_tolerance_mm of it (InterferenceContext::cable_cad); "reaches": within label_tolerance_mm plus the samples'
  // spacing of an untraced sample (InterferenceContext::own_cad_samples). An object lying on or near the traced cable
  // lies no nearer its CAD than its measured surface; to be taken for the cable's own it would have to lie on the
  // cable's CAD where the cable is not, and reach its CAD farther than the trace's cover from the measured cable.
  // Reported to the caller (InterferenceContext::untraced_parts), not inspected.
  double own_part_min_fraction = 0.5;
  double own_part_margin_mm = 0.5;
  std::size_t own_part_max_points = 4000;
};

struct Interference {
  std::optional<std::string> with;      // the element's name; nullopt: a foreign object
  int with_element = -1;                // scene element (rigid, or the other cable's CAD), -1 for foreign
  int with_cable = -1;                  // index in the cables list when the other object is a measured cable
  double min_distance_mm = 0.0;         // surface-to-surface gap
  std::vector<std::uint32_t> points;    // cloud indices, increasing
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d closest_on_cable = Eigen::Vector3d::Zero();  // the gap's two ends (axis side: on the surface)
  Eigen::Vector3d closest_on_other = Eigen::Vector3d::Zero();
  std::size_t occluding_points = 0;     // points hiding the cable from the sensor (over it, on its camera side)
};

// Interferences of cables[which] (found, with a chain). `rigid` indexes the rigid elements' CAD triangles (in
// the cloud's frame); `ignore_elements`: scene elements never reported (the cable's own, its attached list).
// Sorted by gap, then by first point. Deterministic for any thread count.
std::vector<Interference> find_interferences(const Cloud& cloud, const KdTree& tree, const Scene& scene,
                                             const SurfaceIndex& rigid, const std::vector<MeasuredCable>& cables,
                                             std::size_t which, const std::vector<int>& ignore_elements,
                                             const InterferenceParams& params);

// Optional extra knowledge for the labelling: the other cables' CAD surfaces (an index over the cable
// elements), and a test "p is hidden from the sensor by a rigid CAD surface" (then p is a mixed pixel of that
// element's silhouette, never a surface seen there). Either may be empty.
struct InterferenceContext {
  const SurfaceIndex* cable_cad = nullptr;
  // true when p is hidden from the sensor by a CAD surface (any element but this cable)
  std::function<bool(const Eigen::Vector3d&)> hidden_by_rigid;
  // The cable's own registered CAD samples (its trace's seeds, own_cad_spacing_mm apart) and the distance from its
  // measured chain within which a sample counts as traced (InterferenceParams::own_part_*). Null (or no cable_cad):
  // no such test.
  const std::vector<Eigen::Vector3d>* own_cad_samples = nullptr;
  double own_cad_spacing_mm = 0.0;
  double own_cad_traced_within_mm = 0.0;
  // Out (optional): the centre of each cluster left out as the cable's own untraced part.
  std::vector<Eigen::Vector3d>* untraced_parts = nullptr;
};
std::vector<Interference> find_interferences(const Cloud& cloud, const KdTree& tree, const Scene& scene,
                                             const SurfaceIndex& rigid, const std::vector<MeasuredCable>& cables,
                                             std::size_t which, const std::vector<int>& ignore_elements,
                                             const InterferenceParams& params, const InterferenceContext& context);

}  // namespace ewis
