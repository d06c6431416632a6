#pragma once
// What `ewis register` reads as --source/--target: a point cloud (as --scan) or a mesh (as --cad).
// Mesh formats by extension (obj, stl, gltf, glb, off, 3ds, dae, fbx, ...); a .ply is a mesh when its header
// declares faces, else a point cloud.
#include <memory>
#include <string>

#include "ewis/core/cloud.hpp"
#include "ewis/io/cloud_io.hpp"
#include "ewis/scene/scene.hpp"

namespace ewis {

struct RegistrationInput {
  bool is_mesh = false;
  Scene scene;  // when is_mesh (CAD units: mm)
  Cloud cloud;  // when a point cloud (scaled to mm by the unit)
};

// True when `path` should be read as a mesh (see above). Throws InputError for a .ply that cannot be opened.
bool is_mesh_file(const std::string& path);

// Reads either kind; `cloud_unit` scales point clouds only (meshes are CAD: mm). Throws InputError.
RegistrationInput read_registration_input(const std::string& path, LengthUnit cloud_unit = LengthUnit::Millimetre);

}  // namespace ewis
