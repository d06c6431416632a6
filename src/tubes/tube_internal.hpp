#pragma once
// Internals shared by the files of the tubes stage (not part of the public API).
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include "ewis/core/cloud.hpp"
#include "ewis/search/kdtree.hpp"
#include "ewis/tubes/cylinder_fit.hpp"
#include "ewis/tubes/trace.hpp"

namespace ewis::tubes_detail {

// Everything one trace needs; built once per trace (no global state).
struct Context {
  const Cloud& cloud;
  const KdTree& tree;
  const TubeParams& params;
  double resolution_mm = 1.0;
  double tolerance_mm = 0.5;   // shell half-width around the surface
  double step_mm = 5.0;        // sub-cable length
  double half_window_mm = 4.0; // half-length of the fit window around each new joint
  double expected_density = 0; // fitted inliers per mm of tube (from the initial fit)
  bool thin = false;           // TubeParams::thin_max_px: the radius held at the hint in every fit
  std::vector<Eigen::Vector3d> coarse;  // search cone around +z (paper 4.2.2 direction set)
  std::vector<Eigen::Vector3d> fine1, fine2;  // refinement cones (coarse-to-fine)
  std::vector<Eigen::Vector3d> bridge;        // the narrow cone searched across a gap
  std::vector<Neighbor> scratch;
  std::unordered_map<std::uint32_t, Eigen::Vector3f> normals;  // per scan point, towards the sensor (facing_check)

  Context(const Cloud& c, const KdTree& t, const TubeParams& p) : cloud(c), tree(t), params(p) {}
  bool usable(std::uint32_t i) const { return !params.usable || (i < params.usable->size() && (*params.usable)[i]); }
  // `origin`: what the fitted points are relative to (gather's origin); the sensor is given relative to it too.
  CylinderFitParams fit_params(double radius_mm, const Eigen::Vector3d& origin) const;
};

// Usable scan points within `radius` of `center`, relative to `origin` (double), with their indices.
void gather(Context& ctx, const Eigen::Vector3d& center, double radius, const Eigen::Vector3d& origin,
            std::vector<Eigen::Vector3d>& rel, std::vector<std::uint32_t>* ids = nullptr);

// Whether the ray from `sensor` to `q` passes within `radius_mm` of the axis (through `axis_point` along unit
// `axis`) more than `margin_mm` before it reaches q, at an axial position (measured from the frame's origin
// along `axis`) in [t0, t1]: the tube of that radius hides q from the sensor, so q is a mixed pixel or another
// depth error, not a surface. A surface point of the tube itself lies where its ray enters the tube, before
// the ray's closest approach to the axis (up to the noise along the ray: the margin).
bool behind_tube(const Eigen::Vector3d& sensor, const Eigen::Vector3d& q, const Eigen::Vector3d& axis_point,
                 const Eigen::Vector3d& axis, double radius_mm, double margin_mm, double t0, double t1);

// Whether the tube of `radius_mm` along unit `axis` through `axis_point` (relative to `origin`) is in front as the
// sensor sees it: fewer than 3 scan points (any, usable or not: another run's or a rigid element's hide it as well)
// within max(resolution, r/4) of the ray from its point nearest the sensor towards the sensor, over max(10 r, 30 mm).
// True without a sensor.
bool front_clear(Context& ctx, const Eigen::Vector3d& origin, const Eigen::Vector3d& axis_point,
                 const Eigen::Vector3d& axis, double radius_mm);

// What drop_hidden_by_tube did: None, the tube hides no points; Dropped, it hides some and is itself in front
// (front_clear), they were dropped; Kept, it is not in front, or there is no sensor or no hidden_check.
enum class HiddenPoints { None, Dropped, Kept };

// TubeParams::hidden_check: drops from `rel` (relative to `origin`, ids alongside) the points hidden by the tube of
// `radius_mm` along unit `dir` through the origin, between t0 and t1 along it (behind_tube, margin
// ctx.tolerance_mm), when the tube is itself in front (front_clear at the middle of [t0, t1]).
HiddenPoints drop_hidden_by_tube(Context& ctx, std::vector<Eigen::Vector3d>& rel, std::vector<std::uint32_t>& ids,
                                 const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double radius_mm,
                                 double t0, double t1);

// TubeParams::facing_check: drops from `win` (relative to the gather origin, ids alongside) the points whose
// normal points against the direction from the axis (through that origin along unit `axis`) to them. Nothing is
// dropped without a sensor, or when the check would leave fewer than half the points (normals smeared across a
// tube only a few points wide).
void drop_facing_away(Context& ctx, std::vector<Eigen::Vector3d>& win, std::vector<std::uint32_t>& ids,
                      const Eigen::Vector3d& axis);

// paper 4.2.2: the fullest candidate cylinder (axis through the origin of `rel`, radius r) among the
// directions `dirs` rotated onto `around`; counts points in the shell |dist - r| <= tol with t in [t0, t1].
// Coarse-to-fine: then the fine cones around the winner. Returns the best direction and its count.
Eigen::Vector3d search_direction(const Context& ctx, const std::vector<Eigen::Vector3d>& rel,
                                 const Eigen::Vector3d& around, const std::vector<Eigen::Vector3d>& dirs,
                                 double r, double tol, double t0, double t1, int& best_count);

struct AxisState {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // on the axis
  Eigen::Vector3d dir = Eigen::Vector3d::UnitZ();
  double radius_mm = 0;
  double rms_mm = 0;
  int inliers = 0;
  double window_mm = 0;  // axial length of the window the fit used
  double arc_deg = 0;    // angular extent of the fitted surface seen
};

// paper 4.2.1 / 4.2.2: a cylinder near surface point p0 (radius estimated when hint <= 0).
bool initialise_at(Context& ctx, const Eigen::Vector3d& p0, double radius_hint, AxisState& out);

struct StepResult {
  bool ok = false;
  bool partial = false;  // the data end inside this step (the sub-cable is shorter)
  Eigen::Vector3d start = Eigen::Vector3d::Zero(), end = Eigen::Vector3d::Zero(), dir = Eigen::Vector3d::UnitZ();
  double radius_mm = 0, rms_mm = 0, arc_deg = 0;
  std::uint32_t points = 0;
  std::string fail;
};

// paper 4.2.3-4.2.4: one sub-cable from axis point a along d. `bridging`: a is extrapolated across a gap,
// the search is narrower and the data must be there from the start.
// `arc_ref_deg`: the arc of the tube seen so far; a fit over much less is a strip of something else (the
// plane a tube lies on), not this tube.
// `scale` < 1: a shorter step (and window), tried where a full one fails (a bend, the tube's end on a plane).
// `rms_ref_mm`: the fit residual seen so far (the sensor's noise on this tube).
StepResult propagate_step(Context& ctx, const Eigen::Vector3d& a, const Eigen::Vector3d& d, double r_ref,
                          double arc_ref_deg, double rms_ref_mm, bool bridging, double scale = 1.0);

// Measures the local resolution (median nearest-neighbour distance) around p.
double local_resolution(const KdTree& tree, const Eigen::Vector3d& p);

// Whether a tube traced with `p` at this resolution is thin (TubeParams::thin_max_px): its radius held at the hint.
inline bool thin_tube(const TubeParams& p, double resolution_mm) {
  return p.radius_mm > 0 && resolution_mm > 0 && 2.0 * p.radius_mm < p.thin_max_px * resolution_mm;
}

}  // namespace ewis::tubes_detail
