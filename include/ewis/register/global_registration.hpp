#pragma once
// Global registration without an initial pose (needed when `--pose` is absent): FPFH features on
// voxel-down-sampled clouds, RANSAC over 3-point correspondences with edge-length pre-rejection (as PCL's
// SampleConsensusPrerejective / Open3D's RANSAC with CorrespondenceCheckerBasedOnEdgeLength), then point-to-plane
// ICP on the down-sampled clouds. The best few hypotheses are each refined and the one with the highest ICP
// fitness wins; when none reaches min_fitness the next voxel scale is tried.
#include <cstdint>
#include <vector>

#include "ewis/core/cloud.hpp"
#include "ewis/core/progress.hpp"
#include "ewis/register/icp.hpp"

namespace ewis {

struct GlobalRegistrationParams {
  double voxel_mm = 0.0;                // <= 0: bounding-box diagonal / voxel_div, of the smaller cloud ...
  double voxel_div = 40.0;
  // ... (false: of the source). A scan whose background (a floor 150 mm under the scene, larger than the view)
  // doubles its diagonal drew features of twice the scene's scale: 2 of 10 such scans found no pose, 1 the
  // floor matched onto the scene's plate (28 deg off); sized by the CAD, 10 of 10 register within 0.05 mm.
  bool voxel_from_smaller_cloud = true;
  std::vector<double> scale_factors = {1.0, 0.7, 1.4};  // voxel multipliers tried in turn until one validates
  int normal_k = 16;                    // PCA normals of clouds without (triangle) normals
  double feature_radius_factor = 5.0;   // FPFH radius = factor x voxel
  int correspondence_randomness = 3;    // a sampled source point takes one of its k nearest target features
  double sample_fraction = 0.4;         // RANSAC draws from this most-curved fraction of the source points
  double edge_similarity = 0.9;         // pre-rejection: shorter / longer edge of each pair >= this
  double min_edge_factor = 2.0;         // sampled points at least this many voxels apart (well-conditioned)
  double inlier_distance_factor = 1.5;  // RANSAC inlier distance = factor x voxel
  int max_iterations = 120000;          // RANSAC hypotheses drawn per scale (bounded; deterministic)
  std::size_t probe_points = 400;       // source points scoring each surviving hypothesis
  int candidates = 30;                   // best distinct hypotheses refined by ICP
  double min_fitness = 0.25;            // validation: ICP fitness (at 1 voxel) of the chosen pose
  bool try_all_scales = false;          // true: every scale runs and `candidates` pools all of them
  std::uint64_t seed = 1;
  // Normals of clouds without normals point toward these (each cloud's sensor; the scan frame's origin).
  Eigen::Vector3d source_viewpoint = Eigen::Vector3d::Zero();
  Eigen::Vector3d target_viewpoint = Eigen::Vector3d::Zero();
};

struct GlobalRegistrationResult {
  RegistrationResult registration;  // after ICP on the down-sampled clouds (fitness at 1 voxel)
  bool valid = false;               // registration.fitness >= min_fitness
  double voxel_mm = 0.0;            // the scale that gave the result
  int scales_tried = 0;
  std::size_t correspondences = 0;  // feature correspondences at that scale (source points x randomness)
  std::size_t hypotheses_scored = 0;  // hypotheses that passed pre-rejection
  // Every refined candidate of the chosen scale (all scales with try_all_scales), best fitness first (the first is `registration`): callers with
  // a finer test (full-resolution ICP) may re-rank the first few, as symmetric scenes make near-ties.
  std::vector<RegistrationResult> candidates;
};

// Registers source onto target with no initial pose. Uses the clouds' normals when present (CAD samples carry
// triangle normals), else PCA normals toward the viewpoints. Deterministic for a seed and any thread count.
GlobalRegistrationResult register_global(const Cloud& source, const Cloud& target,
                                         const GlobalRegistrationParams& params = {},
                                         const ProgressFn& progress = {});

}  // namespace ewis
