#pragma once
// Internal to the raycast stage: the rays of one 4x4 pixel block from a pinhole camera, cast straight into
// Embree packets (no Ray/Hit structs per pixel: render() spends most of its time here).
#include <Eigen/Core>
#include <cstdint>

#include "ewis/raycast/raycaster.hpp"

namespace ewis::detail {

struct CameraBlock {
  Eigen::Vector3f origin;
  alignas(64) float dx[16] = {};  // unit directions, lanes [0, count); later lanes are ignored
  alignas(64) float dy[16] = {};
  alignas(64) float dz[16] = {};
  int count = 0;
};

struct CameraHits {
  float distance_mm[16];
  std::uint32_t element[16];      // kNoElement: no hit
  Eigen::Vector3f normal[16];     // unit, facing the ray; only filled when `want_normals`
};

struct RaycasterAccess {
  static void cast_camera_block(const Raycaster& caster, const CameraBlock& block, CameraHits& hits,
                                bool want_normals);
};

}  // namespace ewis::detail
