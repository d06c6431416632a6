// CAD loading: PLY and OBJ by our own readers, every other format through Assimp 5.2.
#include <Eigen/Geometry>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <system_error>

#include "ewis/core/error.hpp"
#include "ewis/core/scratch.hpp"
#include "ewis/scene/scene.hpp"
#include "import_assimp.hpp"
#include "read_obj_mesh.hpp"
#include "read_ply_mesh.hpp"

namespace ewis {
namespace {

Scene load_ply(const std::string& path, std::size_t* dropped_degenerate) {
  std::ifstream f(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (!f && !f.eof()) throw InputError(path, "cannot read file");
  detail::PlyMesh ply = detail::read_ply_mesh(path, bytes);
  std::size_t degenerate = 0;
  std::vector<Eigen::Vector3i> kept;
  kept.reserve(ply.triangles.size());
  for (const Eigen::Vector3i& t : ply.triangles) {
    const Eigen::Vector3d a = ply.vertices[t[0]].cast<double>();
    const double area2 = (ply.vertices[t[1]].cast<double>() - a).cross(ply.vertices[t[2]].cast<double>() - a).norm();
    if (area2 > 0.0 && std::isfinite(area2)) kept.push_back(t);
    else ++degenerate;
  }
  if (dropped_degenerate) *dropped_degenerate = degenerate;
  if (kept.empty())
    throw InputError(path, degenerate > 0 ? "mesh has only degenerate (zero-area) triangles" : "mesh has no triangles");
  Scene scene;
  add_element(scene, std::filesystem::path(path).stem().string(), ply.vertices, kept);
  return scene;
}

}  // namespace

Scene load_scene(const std::string& path, std::size_t* dropped_degenerate) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path p(path);
  if (!fs::exists(p, ec)) throw InputError(path, "file not found");
  if (fs::is_directory(p, ec)) throw InputError(path, "is a directory, expected a mesh file");
  const auto size = fs::file_size(p, ec);
  if (ec) throw InputError(path, "cannot read file: " + ec.message());
  if (size == 0) throw InputError(path, "file is empty");

  // PLY is read here, not by Assimp 5.2, whose PLY importer hangs on a truncated header and crashes on a
  // truncated binary body. One element per file, named after the file stem.
  // Assimp recognises PLY by a case-insensitive "ply" token near the start, so every spelling (and every
  // .ply name) comes here, after leading white space (found by fuzzing: "Ply"/"pLy" crashed or hung Assimp).
  std::string head(64, '\0');
  {
    std::ifstream f(p, std::ios::binary);
    f.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(f.gcount()));
  }
  const std::size_t first = head.find_first_not_of(" \t\r\n\f\v");
  std::string magic = first == std::string::npos ? std::string() : head.substr(first, 3);
  for (auto& c : magic) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::string ext = p.extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (magic == "ply" || ext == ".ply") return load_ply(path, dropped_degenerate);
  // OBJ is streamed by our own reader: Assimp's import of a 5.6 MB OBJ peaked at 64 MB (a copy per face
  // corner, then JoinIdenticalVertices); ours holds the file's vertices and the Scene.
  if (ext == ".obj") return detail::read_obj_mesh(path, dropped_degenerate);

  Scene scene = detail::import_with_assimp(path, dropped_degenerate);
  return_free_heap_to_os();  // Assimp's many small transient blocks (core/scratch.hpp)
  return scene;
}

}  // namespace ewis
