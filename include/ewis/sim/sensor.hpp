#pragma once
// Virtual structured-light sensor (Ensenso N35 class, paper 2.1.1 and 5): a pinhole camera and a projector
// offset by a baseline along the camera's x axis. A pixel measures a point only where the surface is seen by
// the camera AND lit by the projector (stereo shadowing), at incidence angles below a limit for both.
// Noise is Gaussian along the camera ray, growing with the square of the range; outliers (paper Fig. 7:
// ~40% of the cloud) are isolated points, small clusters of "flying pixels" and mixed pixels at depth
// discontinuities. Points are in the SENSOR frame (mm).
#include <cstdint>
#include <vector>

#include "ewis/core/camera.hpp"
#include "ewis/core/cloud.hpp"
#include "ewis/core/pose.hpp"
#include "ewis/raycast/raycaster.hpp"

namespace ewis::sim {

struct SensorParams {
  double baseline_mm = 100.0;          // projector at camera (+baseline, 0, 0)
  double max_incidence_deg = 75.0;     // for the camera ray and the projector ray
  double sigma600_mm = 0.2;            // noise sigma along the ray at 600 mm; sigma = sigma600 (d/600)^2
  double outlier_fraction = 0.4;       // of the OUTPUT cloud, in [0, 0.95]
  double isolated_share = 0.5;         // shares of the outliers: isolated points,
  double flying_share = 0.25;          // clusters of 2-4 flying pixels,
  double mixed_share = 0.25;           // mixed pixels at depth edges (the rest goes to isolated points)
  // Stereo-mismatch patches (a stereo sensor's matching errors on shiny or dark spots): this many square patches of
  // mismatch_min_px..mismatch_max_px pixels a side, anchored on measured pixels, whose depths are all off by the same
  // mismatch_min_mm..mismatch_max_mm (either sign) along their rays, over the one surface at the anchor (pixels
  // within 5 mm of its depth). They replace the pixels' surface points (one depth per pixel): dense clumps that
  // radius outlier removal keeps. 0 (default): none.
  int mismatch_patches = 0;
  int mismatch_min_px = 2, mismatch_max_px = 6;
  double mismatch_min_mm = 1.0, mismatch_max_mm = 10.0;
  double min_range_mm = 100.0, max_range_mm = 3000.0;
  std::uint64_t seed = 1;
  bool noise_free = false;             // sigma 0 and no outliers (tests)
};

enum class PointKind : std::uint8_t { Surface = 0, Isolated = 1, Flying = 2, Mixed = 3, Mismatch = 4 };

struct ScanResult {
  Cloud cloud;                           // sensor frame, mm
  std::vector<PointKind> kind;           // per point
  std::vector<std::uint32_t> element;    // scene element of surface points; kNoElement for outliers
  std::vector<std::uint32_t> pixel;      // row * width + col of each point
  std::size_t surface_points = 0, outliers = 0;
  std::size_t mismatched = 0;            // surface points moved by mismatch patches (counted in surface_points)
  std::size_t camera_hits = 0;           // pixels whose camera ray hit something
  std::size_t shadowed = 0;              // hit, but the projector's ray was blocked
  std::size_t grazing = 0;               // hit, but an incidence angle was above the limit
};

// Scans `caster`'s scene from `camera_to_world`. Deterministic for a seed, for any thread count.
ScanResult scan(const Raycaster& caster, const Camera& camera, const Pose& camera_to_world, const SensorParams& params);

}  // namespace ewis::sim
