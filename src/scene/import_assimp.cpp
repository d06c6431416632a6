// CAD import through Assimp 5.2 (every format but PLY and OBJ): one element per node/object name, node
// transforms applied.
#include "import_assimp.hpp"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <Eigen/Geometry>
#include <assimp/Importer.hpp>
#include <cmath>
#include <filesystem>
#include <map>

#include "ewis/core/error.hpp"

namespace ewis::detail {
namespace {

struct Part {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3i> triangles;
};

// Assimp names the root of formats without a node hierarchy "<STL_ASCII>", "<PLY_Root>", "$$$DUMMY" ...;
// such names (and empty ones) are not element names.
bool synthetic_name(const std::string& name) {
  return name.empty() || name.front() == '<' || name.rfind("$$$", 0) == 0 || name == "ROOT";
}

struct Collector {
  const aiScene* ai = nullptr;
  std::string file_stem;
  std::string file_name;
  std::vector<std::string> order;  // element names in order of first appearance (node tree, depth first)
  std::map<std::string, Part> parts;
  std::size_t degenerate = 0;
  std::size_t triangle_total = 0;

  std::string element_name(const aiNode* node, const aiMesh* mesh) const {
    std::string n = node->mName.C_Str();
    // The OBJ importer names its root node after the file; meshes hang below it only when faces precede
    // any `o`/`g`, and those faces belong to the file as a whole.
    if (!synthetic_name(n) && !(node == ai->mRootNode && n == file_name)) return n;
    const std::string m = mesh->mName.C_Str();
    if (!synthetic_name(m)) return m;  // e.g. ASCII STL: each `solid NAME` is a mesh of the root node
    if (!synthetic_name(n)) return n;
    return file_stem;
  }

  void add_mesh(const aiMesh* mesh, const aiMatrix4x4& m, const std::string& name) {
    if (parts.find(name) == parts.end()) order.push_back(name);
    Part& part = parts[name];
    const int offset = static_cast<int>(part.vertices.size());
    part.vertices.reserve(part.vertices.size() + mesh->mNumVertices);
    for (unsigned i = 0; i < mesh->mNumVertices; ++i) {
      const aiVector3D v = m * mesh->mVertices[i];
      part.vertices.emplace_back(v.x, v.y, v.z);
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines are not surfaces
      const Eigen::Vector3i t(int(face.mIndices[0]), int(face.mIndices[1]), int(face.mIndices[2]));
      if (t.maxCoeff() >= int(mesh->mNumVertices)) continue;
      ++triangle_total;
      const Eigen::Vector3d a = part.vertices[offset + t[0]].cast<double>();
      const Eigen::Vector3d b = part.vertices[offset + t[1]].cast<double>();
      const Eigen::Vector3d c = part.vertices[offset + t[2]].cast<double>();
      const double area2 = (b - a).cross(c - a).norm();
      if (!(area2 > 0.0) || !std::isfinite(area2)) {  // zero area or NaN/inf coordinates
        ++degenerate;
        continue;
      }
      part.triangles.push_back(t.array() + offset);
    }
  }

  // Depth-first with an explicit stack (a malicious file could nest nodes deeply); bounded by the node count.
  void walk() {
    std::vector<std::pair<const aiNode*, aiMatrix4x4>> stack{{ai->mRootNode, ai->mRootNode->mTransformation}};
    std::size_t visited = 0;
    const std::size_t limit = 100'000'000;
    while (!stack.empty() && visited++ < limit) {
      auto [node, m] = stack.back();
      stack.pop_back();
      for (unsigned i = 0; i < node->mNumMeshes; ++i) {
        if (node->mMeshes[i] >= ai->mNumMeshes) continue;
        const aiMesh* mesh = ai->mMeshes[node->mMeshes[i]];
        add_mesh(mesh, m, element_name(node, mesh));
      }
      // Push children in reverse so they are visited in file order.
      for (unsigned c = node->mNumChildren; c-- > 0;) {
        const aiNode* child = node->mChildren[c];
        if (child) stack.emplace_back(child, m * child->mTransformation);
      }
    }
  }
};

}  // namespace

// Any other format, through Assimp: one element per object name (merged), triangles only.
Scene import_with_assimp(const std::string& path, std::size_t* dropped_degenerate) {
  const std::filesystem::path p(path);
  // No DefaultLogger is created, so Assimp logs to its NullLogger (silent).
  Assimp::Importer importer;
  // Triangulate polygons; JoinIdenticalVertices gives indexed meshes. Deliberately NOT OptimizeMeshes,
  // OptimizeGraph or PreTransformVertices: they merge meshes and lose the object names (DESIGN.md).
  const aiScene* ai = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices);
  if (!ai) throw InputError(path, std::string("cannot import mesh: ") + importer.GetErrorString());
  if (!ai->mRootNode) throw InputError(path, "mesh file has no scene graph");

  Collector collect;
  collect.ai = ai;
  collect.file_stem = p.stem().string();
  collect.file_name = p.filename().string();
  collect.walk();

  Scene scene;
  for (const std::string& name : collect.order) {
    const Part& part = collect.parts[name];
    if (part.triangles.empty()) continue;
    add_element(scene, name, part.vertices, part.triangles);
  }
  if (dropped_degenerate) *dropped_degenerate = collect.degenerate;
  if (scene.triangles.empty())
    throw InputError(path, collect.degenerate > 0 ? "mesh has only degenerate (zero-area) triangles"
                                                  : "mesh has no triangles");
  return scene;
}

}  // namespace ewis::detail
