#pragma once
// Internal to the scene stage: a streaming Wavefront OBJ reader that builds the Scene the Assimp 5.2 path built
// (same element names and order, same triangles and vertex numbering) without Assimp's per-corner copies.
#include <cstddef>
#include <string>

#include "ewis/scene/scene.hpp"

namespace ewis::detail {

// Reads the file in chunks; holds the file's vertex positions and the Scene being built, not the file.
// Degenerate (zero-area, NaN/inf) triangles are dropped and counted in `dropped_degenerate` when given.
// Throws InputError(path, "line N: what") on malformed numbers, face index 0 or out of range, a vertex line
// without 3, 4 or 6 numbers; InputError(path, what) on an unreadable file or one without triangles.
Scene read_obj_mesh(const std::string& path, std::size_t* dropped_degenerate);

}  // namespace ewis::detail
