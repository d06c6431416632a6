#pragma once
// Cloud-to-cloud registration (`ewis register` between two point clouds): target normals estimated by PCA,
// global registration when no initial pose is given, then point-to-plane ICP.
#include <optional>

#include "ewis/register/global_registration.hpp"
#include "ewis/register/icp.hpp"

namespace ewis {

struct CloudRegistrationParams {
  IcpParams icp;                     // final_max_distance_mm <= 0: max(1 mm, 3 x target, 1.5 x source resolution)
  GlobalRegistrationParams global;
  int normal_k = 16;
  double min_fitness = 0.25;
  CloudRegistrationParams() { icp.final_max_distance_mm = 0.0; icp.expected_error_mm = 20.0; }
};

struct CloudRegistrationResult {
  RegistrationResult registration;
  bool valid = false;
  bool used_global = false;
  double target_resolution_mm = 0.0;
};

// Target normals: its own when present, else PCA (oriented toward params.global.target_viewpoint).
CloudRegistrationResult register_clouds(const Cloud& source, const Cloud& target,
                                        const std::optional<Pose>& initial_source_to_target,
                                        const CloudRegistrationParams& params = {},
                                        const ProgressFn& progress = {});

}  // namespace ewis
