#pragma once
// The CAD scene: one triangle soup where every triangle knows its element (object/node name).
// Triangles of one element are contiguous: [first_triangle, first_triangle + triangle_count).
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace ewis {

struct Element {
  std::string name;
  std::uint32_t first_triangle = 0;
  std::uint32_t triangle_count = 0;
  double area_mm2 = 0.0;
  Eigen::Vector3d center_of_mass = Eigen::Vector3d::Zero();  // area-weighted surface centroid
  Eigen::Vector3d bounds_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d bounds_max = Eigen::Vector3d::Zero();
  std::uint32_t reoriented_triangles = 0;  // wound inside out or against their neighbours in the file (orient_faces.hpp)
};

struct Scene {
  std::vector<Eigen::Vector3f> vertices;        // mm
  std::vector<Eigen::Vector3i> triangles;       // vertex indices
  std::vector<std::uint32_t> triangle_element;  // element index per triangle
  std::vector<Element> elements;

  // Index of the element with this name, or -1.
  int find(const std::string& name) const;
  std::size_t triangle_count() const { return triangles.size(); }
};

// Appends one element (its own vertices and triangles) and computes its area, centre and bounds.
// An element of the same name already present is extended (its triangles stay contiguous only when
// appended last; load_scene merges same-named meshes before appending).
void add_element(Scene& scene, const std::string& name, const std::vector<Eigen::Vector3f>& vertices,
                 const std::vector<Eigen::Vector3i>& triangles);

// Recomputes area, centre of mass and bounds of every element.
void update_element_stats(Scene& scene);

// Loads OBJ/STL/PLY/glTF/... through Assimp (no merging post-processes, so names survive); meshes of the
// same node/object name form one element. Degenerate (zero-area) triangles are dropped and counted in
// `dropped_degenerate` when given. The faces' winding is left as written (orient_faces.hpp repairs it).
// Throws InputError(path, what) on a missing, unreadable or empty file.
Scene load_scene(const std::string& path, std::size_t* dropped_degenerate = nullptr);

// Writes a Wavefront OBJ with one `o NAME` per element (atomic: temporary file + rename). Blanks in names
// are written as '_' (Assimp ends OBJ object names at a blank).
void write_obj(const Scene& scene, const std::string& path);

}  // namespace ewis
