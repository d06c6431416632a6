#pragma once
// Tracing a tube (cable, hose, pipe, branch) through a scan as a chain of cylinders: the search structure of
// paper 4.2 (initialisation 4.2.1, sphere + antipodal points 4.2.2, sub-cable fit 4.2.3, propagation 4.2.4).
// Self-contained: needs only the scan and its k-d tree (the "cylindrical shape segmentation library").
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "ewis/core/cloud.hpp"
#include "ewis/core/cylinder.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis {

struct TubeParams {
  double radius_mm = 0.0;          // expected radius (a hint); <= 0: estimated at the seed
  double resolution_mm = 0.0;      // scan point spacing; <= 0: measured near the seed
  double max_length_mm = 20000.0;  // hard bound on the traced length (no endless loops)
  double max_gap_mm = 0.0;         // longest stretch bridged without data; <= 0: 3 x diameter
  // Optional: called with a candidate centreline point; true stops the trace there (e.g. the cable enters
  // an attached clamp or connector). Called once per step (a few more at the last one), never per point.
  std::function<bool(const Eigen::Vector3d&)> stop_at;
  // Optional: per scan point, 0 = not usable (e.g. belongs to a rigid CAD element); empty: all usable.
  const std::vector<std::uint8_t>* usable = nullptr;

  // Optional sensor position (scan frame; the origin when the scan is in the sensor frame): residuals of
  // the sub-cable fit are then measured along the camera rays, the direction of the sensor's noise.
  bool has_sensor = false;
  Eigen::Vector3d sensor_position = Eigen::Vector3d::Zero();
  // With the sensor: each fit leaves out the points whose surface normal (local PCA, turned towards the sensor)
  // points against the direction from the axis to them (cosine below facing_min_cos). A solid tube's seen
  // surface faces away from its axis; the sliver of a touching neighbour beside the contact (a bundle) lies
  // within the tube's surface band but faces back towards its axis (cosine -0.4 to -0.9).
  bool facing_check = true;
  double facing_min_cos = 0.0;
  // With the sensor: the points a step's tube hides (their ray passes within its radius of the axis before it
  // reaches them, more than the surface tolerance before) are left out of the step and do not count as a surface
  // going on just outside the tube: they are mixed pixels hanging from its silhouette. Only where the tube is
  // itself in front: a "tube" fitted among the mixed points under a cable has that cable between it and the sensor.
  bool hidden_check = true;

  // Propagation (paper 4.2.4); <= 0: derived from the radius and the resolution.
  double step_mm = 0.0;               // sub-cable length (default: one radius, at least 4 x resolution)
  double surface_tolerance_mm = 0.0;  // shell half-width around the fitted surface (default ~0.15 r)
  double max_turn_deg = 35.0;         // larger direction change between neighbouring sub-cables: the end
  double max_radius_change = 0.3;     // larger relative radius change than this: the end
  // A seed whose fitted radius is off the hint (radius_mm) by more than this factor, either way, is refused.
  // 2 for a rough hint; a known nominal radius (inspect) allows less: a seed fitted on a cable and the clamp
  // around it reads wide (1.37x on campaign scene_040) and the run then starts with a fat cylinder.
  double max_seed_radius_ratio = 2.0;
  double search_cone_deg = 30.0;      // directions searched around the current one each step
  // trace_cable only: when no start is found within the radius of the CAD points, look this far from them
  // (a cable displaced from its CAD by more than its radius); <= radius_mm: no second pass.
  double seed_search_mm = 0.0;
  // A thin tube: with a radius hint (radius_mm) whose diameter spans fewer than thin_max_px resolutions, every
  // fit holds the radius at the hint and fits the axis only. A stripe 3-4 points wide does not measure its own
  // curvature against the noise (a 1.7 mm wire under 0.2 mm noise at 0.5 mm spacing: free fits read 0.54-1.37 mm
  // for 0.85, the seeds' "bends beyond the noise" test failed, the wire was not found), while the axis it holds
  // is well measured. Its shell is then at least 3 x the fit's rms wide (up to the radius), and the rms is not
  // capped by the radius. 0: off (the radius is fitted everywhere).
  double thin_max_px = 0.0;
};

struct SubCable {
  Cylinder cylinder;        // start -> end along the trace direction
  std::uint32_t points = 0; // scan points inside (0 for a bridged stretch)
  double rms_mm = 0.0;      // fit residual (distance to the surface)
  bool bridged = false;     // true: a gap bridged without data (its radius is the neighbours')
};

struct TubeGap {
  Eigen::Vector3d start, end;  // bridged without data
};

struct TubeTrace {
  bool found = false;
  Eigen::Vector3d seed = Eigen::Vector3d::Zero();
  double radius_mm = 0.0;                      // measured (median over the fitted sub-cables)
  double rms_mm = 0.0;                         // median fit residual of the sub-cables
  std::vector<SubCable> segments;              // ordered from one end to the other, end_i == start_{i+1}
                                               // (gaps appear as `bridged` sub-cables and in `gaps`)
  std::vector<Eigen::Vector3d> centerline;     // smooth, end to end, consecutive points <= radius apart
  double length_mm = 0.0;                      // centreline length
  std::vector<std::uint32_t> points;           // scan points assigned to the tube (paper 4.3.2 set S), sorted
  std::vector<TubeGap> gaps;
  std::string end_reason_front, end_reason_back;  // why each end stopped ("no data", "stop region", ...)
};

// Traces the tube through (or nearest to) `seed`, in both directions.
TubeTrace trace_tube(const Cloud& cloud, const KdTree& tree, const Eigen::Vector3d& seed, const TubeParams& params);

// CAD-guided tracing (paper 4.2.1): `cad_points` are the registered CAD cable's sample points (scan frame);
// the start sphere is chosen among them by the count of scan points inside a sphere of the cable radius,
// refined by the two-step re-centring of Fig. 8d, falling back to the next candidate when it fails.
TubeTrace trace_cable(const Cloud& cloud, const KdTree& tree, const std::vector<Eigen::Vector3d>& cad_points,
                      double radius_mm, const TubeParams& params);

// --- helpers on a finished trace ---

// Distance from p to the traced chain's axis (segments, bridged ones included); infinity when empty.
double distance_to_chain(const TubeTrace& trace, const Eigen::Vector3d& p);

// Fraction (0..1) of the length of `reference` (a polyline, e.g. the CAD cable's centreline) that lies
// within `tolerance_mm` of the traced chain: the coverage of the measured cable relative to the CAD one.
double chain_coverage(const TubeTrace& trace, const std::vector<Eigen::Vector3d>& reference, double tolerance_mm);

// How many scan points the trace holds for its length, relative to what a tube of its radius shows a sensor at
// `sensor` (same frame) whose points lie resolution_mm apart: each sub-cable's (bridged ones left out) seen width 2 r
// times its length across the ray to the sensor, over resolution_mm squared. About 1 on a tube seen whole; well below
// on a trace walked along stray points. 0 when nothing is expected.
double run_support(const TubeTrace& trace, const Eigen::Vector3d& sensor, double resolution_mm);

// Length of a polyline.
double polyline_length(const std::vector<Eigen::Vector3d>& polyline);

}  // namespace ewis
