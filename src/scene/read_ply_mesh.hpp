#pragma once
// Internal to the scene stage: a strict PLY mesh reader. Assimp 5.2's PLY importer hangs on a truncated
// header and crashes on a truncated binary body, so load_scene reads PLY itself.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace ewis::detail {

struct PlyMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3i> triangles;  // polygons fan-triangulated
};

// Throws InputError(path, what) on anything malformed: never reads past the data, every loop bounded.
PlyMesh read_ply_mesh(const std::string& path, const std::string& bytes);

}  // namespace ewis::detail
