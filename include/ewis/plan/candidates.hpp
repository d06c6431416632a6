#pragma once
// Candidate viewpoints on a sphere around an element (paper 3.2).
//
// Sampling rule (documented in docs/plan.md):
//   position = centre + rho * (sin(phi) cos(theta), sin(phi) sin(theta), cos(phi)),
//   theta (longitude, from +x towards +y) and phi (colatitude, from +z), in degrees.
// - theta: from theta_min every step_deg. A full circle (max - min >= 360) excludes max (it is min again), so
//   [0, 360) with step 10 gives 36 values 0, 10, ..., 350; a partial range includes both ends when they fall
//   on the grid ([0, 90] gives 0, 10, ..., 90).
// - phi: the range is cut into floor(range / step) cells of step_deg, centred in the range, and a candidate
//   sits at each cell's centre: [0, 180] with step 10 gives 5, 15, ..., 175 (18 values), so no candidates
//   pile up on the poles and 10 degrees give 36 x 18 = 648 candidates. A range narrower than one step
//   gives its midpoint.
// - Roll: the camera looks at the centre; world +z, projected onto the image plane, points up in the image
//   (-y of the camera). When the optical axis is within 2.6 degrees of vertical, world +y is used instead.
// Order: phi-major, theta-minor (index = i_phi * n_theta + i_theta); ties and ranks use this order.
#include <Eigen/Core>
#include <vector>

#include "ewis/core/pose.hpp"

namespace ewis {

struct CandidateParams {
  double radius_mm = 600.0;      // rho: distance from the element's centre of mass
  double step_deg = 10.0;        // sampling step of theta and phi
  double theta_min_deg = 0.0;    // longitude range
  double theta_max_deg = 360.0;
  double phi_min_deg = 0.0;      // colatitude range, within [0, 180]
  double phi_max_deg = 180.0;
};

struct Candidate {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // sensor (camera centre), CAD frame, mm
  Eigen::Vector3d target = Eigen::Vector3d::Zero();    // the sphere's centre
  double theta_deg = 0.0, phi_deg = 0.0;
  int theta_index = 0, phi_index = 0;                  // grid cell, for heat maps
  Pose camera_to_cad = Pose::Identity();
};

struct CandidateGrid {
  std::vector<double> theta_deg;  // the sampled longitudes, increasing
  std::vector<double> phi_deg;    // the sampled colatitudes, increasing
  std::vector<Candidate> candidates;  // phi-major, theta-minor
};

// The theta and phi values of the rule above. Throws InputError("", what) on a non-positive step or radius,
// an empty or reversed range, phi outside [0, 180], or more than 1e6 candidates.
std::vector<double> theta_samples_deg(const CandidateParams& params);
std::vector<double> phi_samples_deg(const CandidateParams& params);

// The camera pose of the roll rule above: at `position`, looking at `target`.
Pose candidate_pose(const Eigen::Vector3d& position, const Eigen::Vector3d& target);

CandidateGrid make_candidates(const Eigen::Vector3d& center, const CandidateParams& params);

}  // namespace ewis
