#pragma once
// Small scenes with known answers for the plan tests.
#include <string>

#include "ewis/scene/primitives.hpp"
#include "ewis/scene/scene.hpp"

namespace ewis::test {

inline void add_mesh(Scene& scene, const std::string& name, const Mesh& mesh) {
  add_element(scene, name, mesh.vertices, mesh.triangles);
}

}  // namespace ewis::test
