#pragma once
// A pose the scene hardly fixes along one direction. Point-to-plane ICP feels a translation only through faces whose
// normals have a component along it: on a view filled by a plate with a few small blocks, the position along the
// plate rests on the blocks' side faces and the plate's edges, a small share of the points. Once the coarse pass has
// left the pose several millimetres off along the plate (the scan's surviving outliers and the plate's edges pull
// it there at coarse distances), the fine pass, whose correspondences reach only ~5 mm, no longer reaches those
// faces, and the pose stays off with nearly the fitness of the right one (fresh campaign `--seed 3579 --campaign 40
// --pose-error-deg 8 --pose-error-mm 40 --noise-mm 0.25 --outliers 0.5`, scene_022: 8.95 mm along the plate,
// fitness 0.972 against 0.976 at the true pose, two false foreign objects). So the fitness is probed along the
// weakest direction of translation and, where it rises, the fine pass runs again from its best.
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ewis/core/cloud.hpp"
#include "ewis/core/pose.hpp"
#include "ewis/search/kdtree.hpp"

namespace ewis {

struct WeakDirectionParams {
  bool enabled = true;
  // The weakest direction is probed when its constraint (the smallest eigenvalue of the sum of n n^T over the
  // matched target normals) is under this share of the strongest (scene_022: 0.001; 7 of 12 scenes of the
  // 140-scene campaign, a plate seen from above, 0.004-0.009: docs/register.md "Weakly fixed along the plate").
  double max_ratio = 0.01;
  std::size_t probe_points = 5000;  // evenly strided over the points the fine pass used
  double step_mm = 2.5;             // probe offsets are multiples of this, climbing while the fitness does not fall
  double reach_mm = 30.0;           // ... up to this far each way
  double min_gain = 0.002;          // the best offset must raise the fitness by this much (of the probe points)
  // Probe and fine pass are repeated while the fitness rises, at most this many times: a pose 121 mm along the plate
  // (R40 scene_002, from pose.txt) climbs 30 mm a round; stopped after one round at 0.929 it was trusted 20 mm off.
  int max_rounds = 6;
};

struct WeakDirection {
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // unit, in the target's frame
  double ratio = 1.0;       // smallest over largest eigenvalue; 1 when nothing matched
  std::size_t matched = 0;  // probe points with a target neighbour within the distance
};

// The translation direction the correspondences of `source[indices]` under `source_to_target` (nearest target
// point within distance_mm) constrain least.
WeakDirection weakest_translation(const std::vector<Eigen::Vector3f>& source, const std::vector<std::uint32_t>& indices,
                                  const Cloud& target, const KdTree& target_tree, const Pose& source_to_target,
                                  double distance_mm);

// The offset (mm, along `direction`) at which the fitness of `source[indices]` (inlier distance
// inlier_distance_mm) is highest, climbing from 0 in steps of params.step_mm each way while it does not fall, up
// to params.reach_mm; 0 when no offset beats the pose by params.min_gain. Deterministic.
double best_offset_along(const std::vector<Eigen::Vector3f>& source, const std::vector<std::uint32_t>& indices,
                         const Cloud& target, const KdTree& target_tree, const Pose& source_to_target,
                         const Eigen::Vector3d& direction, double inlier_distance_mm, const WeakDirectionParams& params);

}  // namespace ewis
