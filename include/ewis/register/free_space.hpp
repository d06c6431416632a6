#pragma once
// Free space seen by the sensor: a check of a scan-to-CAD pose that the fitness cannot make. The fitness counts
// scan points near the CAD, so a background the CAD lacks (a floor, the cell) can outscore the scene when a wrong
// pose lays the CAD's plate onto it. But a sensor cannot see through a solid: along every ray on which it measured
// a surface, nothing solid lies nearer. A right pose puts the CAD's faces that face the sensor at or behind what
// each ray measured (behind: a cable or a foreign object in front); a wrong one puts blocks, brackets and pipes in
// front of the measured floor. Counted on the scan's own range image (angular bins in the sensor's frame), so it
// needs no ray casting and no camera model.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ewis/core/cloud.hpp"
#include "ewis/core/pose.hpp"

namespace ewis {

// The nearest measured depth per angular bin (u = x / z, v = y / z) of a scan in its sensor's frame (the
// second-nearest point's: a stray point in front does not hide what the bin saw; a bin of one point: its depth).
struct RangeBins {
  double bin = 0.0;                     // bin size (tangent units); 0: no image (not a sensor's view)
  Eigen::Vector2d lo = Eigen::Vector2d::Zero();
  int width = 0, height = 0;
  std::vector<float> nearest_mm;        // per bin (row-major); +infinity where nothing was measured
};

// The range image of `points` (in the sensor's frame), whatever they look like; points at or behind the sensor's
// plane (z <= 0) are left out, and no image (bin 0) when under 2 are in front. `points_per_bin`: the bins are sized
// so that, were the points spread evenly over their angular box, each would hold about this many (a bin must nearly
// always hold a point of the surface it looks at); no side of the image exceeds that many bins over the points'
// count, so a degenerate spread (rays in one plane) cannot make it huge.
RangeBins bin_depths(const std::vector<Eigen::Vector3f>& points, double points_per_bin);

// The bin of a point in the sensor's frame; -1 behind the sensor or outside the image.
std::ptrdiff_t range_bin(const RangeBins& bins, const Eigen::Vector3d& p);

// The range image of a scan taken as its sensor's view; no image (bin 0) when it does not look like one: under 99 %
// of its points in front of the origin (z > 0), or its rays spread beyond +-63 deg (the registration's check then
// does nothing; sensor_origin.hpp says how inspect reports such a scan).
RangeBins bin_scan_depths(const std::vector<Eigen::Vector3f>& scan, double points_per_bin = 16.0);

struct FreeSpaceCount {
  std::size_t seen = 0;        // CAD samples in front of the sensor, on a bin where something was measured
  std::size_t in_front = 0;    // ... nearer than everything measured there by more than the margin
  double fraction() const { return seen ? static_cast<double>(in_front) / static_cast<double>(seen) : 0.0; }
};

// `cad_samples` in CAD coordinates, with outward normals: those facing the sensor (at scan_to_cad * 0) are
// checked against `bins`. `margin_mm`: how much nearer than the nearest measured depth a sample must be to count.
FreeSpaceCount count_in_front(const RangeBins& bins, const Cloud& cad_samples, const Pose& scan_to_cad,
                              double margin_mm);

}  // namespace ewis
