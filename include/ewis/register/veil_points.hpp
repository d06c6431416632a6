#pragma once
// Veils of mixed pixels (paper 4.1.2, Fig. 7): at a depth edge a structured-light sensor reports depths between
// the foreground and the background on the edge pixel's own ray, so the mixed pixels of one edge form a sheet
// that contains the sensor's rays. Real surfaces are never measured that edge-on (a sensor drops returns beyond
// ~75 deg of incidence), so a point whose local surface contains its viewing ray is a mixed pixel.
//
// Why registration needs this: a veil hangs beside the CAD face behind the edge (e.g. the inner face of a wall
// seen over its top), parallel to it and ~1 mm off; matched to that face it pulls the pose sideways along the
// directions a large plate leaves weak, by far more than the real faces that pin them.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace ewis {

struct VeilParams {
  int k = 16;             // neighbours of the PCA normal (among `points`, the point itself included)
  double cos_max = 0.25;  // a point is a veil point when |cos(normal, viewing ray)| < this (~75.5 deg)
};

// Indices (increasing) of the `points` (in the sensor's frame, the sensor at `viewpoint`) that are NOT veil
// points. Points whose normal is undefined are kept. Deterministic for any thread count.
std::vector<std::uint32_t> points_off_veils(const std::vector<Eigen::Vector3f>& points,
                                            const Eigen::Vector3d& viewpoint, const VeilParams& params = {});

}  // namespace ewis
