#pragma once
// The sensor's angular pixel pitch, measured from a scan taken from `sensor`: around a point of a surface, the points
// whose rays lie within an angle rho of its own ray are the pixels there, about pi rho^2 / pitch^2 of them. The
// nearest-neighbour distance (filter/resolution.hpp) is no pixel: noise across the rays shortens it (0.44 mm for
// pixels 0.52 mm apart under 0.2 mm of isotropic noise: bench/second_scanner.py), and on a tilted surface it is the
// shorter of the two spacings. A count of rays over a disc is what such noise leaves as it was. What a foreign object
// covers in the sensor's view (InterferenceParams::min_object_area_mm2) is counted in these pixels.
#include <cstddef>

#include <Eigen/Core>

#include "ewis/search/kdtree.hpp"

namespace ewis {

struct PixelPitchParams {
  double disc_resolutions = 4.0;    // rho: this many resolutions at the point's range (about 50 pixels in the disc)
  double ball_resolutions = 12.0;   // the ball searched around the point: its surface's disc up to ~70 deg of tilt
  std::size_t min_points = 12;      // a point with fewer in its disc (an edge, a stray point) is not counted
  std::size_t max_samples = 4000;   // evenly strided over the tree's points
};

// The median over the sampled points of rho sqrt(pi / n), in radians; 0 when no point counts (or the resolution or
// the points are unusable). Deterministic for any thread count.
double angular_pixel_pitch_rad(const KdTree& tree, const Eigen::Vector3d& sensor, double resolution_mm,
                               const PixelPitchParams& params = {});

}  // namespace ewis
