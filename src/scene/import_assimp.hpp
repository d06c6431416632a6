#pragma once
// Internal to the scene stage: CAD import through Assimp 5.2, for the formats we do not read ourselves. The
// tests also call it on OBJ files to check that read_obj_mesh gives the Scene this path gave.
#include <cstddef>
#include <string>

#include "ewis/scene/scene.hpp"

namespace ewis::detail {

// One element per node/object name (meshes of one name merged, in order of first appearance), triangles only;
// degenerate triangles dropped and counted. Throws InputError(path, what) when Assimp fails or finds no triangles.
Scene import_with_assimp(const std::string& path, std::size_t* dropped_degenerate);

}  // namespace ewis::detail
